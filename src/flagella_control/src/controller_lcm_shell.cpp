#include "flagella_control/controller_lcm_shell.h"

#include <flagella_lcm/motor_command_t.hpp>
#include <flagella_lcm/slider_command_t.hpp>

namespace flagella::control {

ControllerLcmShell::ControllerLcmShell(lcm::LCM& lcm, ControllerCore& controller,
                                       const std::string& channel_prefix)
    : lcm_(lcm),
      controller_(controller),
      channels_(flagella::LcmChannels::withPrefix(channel_prefix)) {
  lcm_.subscribe(channels_.imu, &ControllerLcmShell::onImu, this);
  lcm_.subscribe(channels_.camera_fix, &ControllerLcmShell::onCameraFix, this);
}

void ControllerLcmShell::onCameraFix(const lcm::ReceiveBuffer*, const std::string&,
                                     const flagella_lcm::point_stamped_t* msg) {
  ++camera_received_;
  fix_.offer(msg->point.x, msg->point.y, msg->point.z, flagella::stampSeconds(msg->header));
}

void ControllerLcmShell::onImu(const lcm::ReceiveBuffer*, const std::string&,
                               const flagella_lcm::imu_t* msg) {
  ++imu_received_;
  inputs_.time = flagella::stampSeconds(msg->header);
  inputs_.imu_valid = true;
  inputs_.orientation[0] = msg->orientation.x;
  inputs_.orientation[1] = msg->orientation.y;
  inputs_.orientation[2] = msg->orientation.z;
  inputs_.orientation[3] = msg->orientation.w;
  inputs_.angular_velocity[0] = msg->angular_velocity.x;
  inputs_.angular_velocity[1] = msg->angular_velocity.y;
  inputs_.angular_velocity[2] = msg->angular_velocity.z;
  inputs_.linear_acceleration[0] = msg->linear_acceleration.x;
  inputs_.linear_acceleration[1] = msg->linear_acceleration.y;
  inputs_.linear_acceleration[2] = msg->linear_acceleration.z;
  last_ = stepWithLatestFix(controller_, inputs_, fix_);  // a fix taken before this sample
  flagella_lcm::motor_command_t command;
  command.header = flagella::lcmHeader(inputs_.time, "");
  command.omega = last_.motor_command;
  lcm_.publish(channels_.motor_command, &command);
  ++commands_published_;
  if (last_.slider_valid) {
    flagella_lcm::slider_command_t slider;
    slider.header = command.header;
    slider.position = last_.slider_position;
    lcm_.publish(channels_.slider_command, &slider);
  }
}

}  // namespace flagella::control
