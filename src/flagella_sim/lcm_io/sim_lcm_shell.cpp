#include "flagella_sim/lcm_io/sim_lcm_shell.h"

#include <flagella_lcm/imu_t.hpp>
#include <flagella_lcm/point_stamped_t.hpp>
#include <flagella_lcm/rod_state_t.hpp>

namespace flagella {

SimLcmShell::SimLcmShell(lcm::LCM& lcm, SimSession& session, const SimLcmOptions& options)
    : lcm_(lcm),
      session_(session),
      options_(options),
      channels_(LcmChannels::withPrefix(options.channel_prefix)),
      schedule_(OutputRates::forSession(session.options(), options.state_rate)) {
  lcm_.subscribe(channels_.motor_command, &SimLcmShell::onMotorCommand, this);
  lcm_.subscribe(channels_.slider_command, &SimLcmShell::onSliderCommand, this);
}

void SimLcmShell::onMotorCommand(const lcm::ReceiveBuffer*, const std::string&,
                                 const flagella_lcm::motor_command_t* msg) {
  ++motor_received_;
  session_.commandMotor(msg->omega);  // the gate rejects and counts bad values
}

void SimLcmShell::onSliderCommand(const lcm::ReceiveBuffer*, const std::string&,
                                  const flagella_lcm::slider_command_t* msg) {
  ++slider_received_;
  session_.commandSlider(msg->position);
}

void SimLcmShell::publishDue(std::map<std::string, long>& published, bool force) {
  const DueOutputs due = schedule_.due(session_.time(), force);
  if (due.rod_state) {
    const RodSnapshot snapshot = session_.snapshot();
    if (snapshot.allFinite()) {
      const flagella_lcm::rod_state_t msg = toRodStateMessage(snapshot, options_.world_frame);
      lcm_.publish(channels_.rod_state, &msg);
      ++published[channels_.rod_state];
    }
  }
  // The camera fix before the IMU sample of the same instant, so the controller step on that
  // sample already has it. Rate 0: off (never due); none inside the dropout window.
  if (due.camera_fix && session_.cameraAvailable()) {
    const CameraFix fix = session_.measureCamera();
    if (fix.position.allFinite()) {
      const flagella_lcm::point_stamped_t msg = toCameraFixMessage(fix, options_.world_frame);
      lcm_.publish(channels_.camera_fix, &msg);
      ++published[channels_.camera_fix];
    }
  }
  if (due.imu) {
    const flagella_lcm::imu_t msg = toImuMessage(session_.measureImu(), options_.imu_frame);
    lcm_.publish(channels_.imu, &msg);
    ++published[channels_.imu];
  }
}

}  // namespace flagella
