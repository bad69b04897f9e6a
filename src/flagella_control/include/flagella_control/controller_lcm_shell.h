// The controller's end of an LCM link: steps a controller core on every IMU sample and publishes
// its motor (and slider) command. A camera fix is handed to the controller on the first step
// after it was taken (pending_fix.h), then dropped. The caller owns the LCM instance and delivers
// its messages.
#pragma once

#include <flagella_lcm/imu_t.hpp>
#include <flagella_lcm/point_stamped_t.hpp>
#include <lcm/lcm-cpp.hpp>
#include <string>

#include "flagella_control/controller_core.h"
#include "flagella_control/pending_fix.h"
#include "flagella_sim/lcm_io/lcm_messages.h"

namespace flagella::control {

class ControllerLcmShell {
 public:
  ControllerLcmShell(lcm::LCM& lcm, ControllerCore& controller, const std::string& channel_prefix);
  long imuReceived() const { return imu_received_; }
  long cameraReceived() const { return camera_received_; }
  long commandsPublished() const { return commands_published_; }
  const ControllerOutputs& lastOutputs() const { return last_; }

 private:
  void onImu(const lcm::ReceiveBuffer*, const std::string&, const flagella_lcm::imu_t* msg);
  void onCameraFix(const lcm::ReceiveBuffer*, const std::string&,
                   const flagella_lcm::point_stamped_t* msg);

  lcm::LCM& lcm_;
  ControllerCore& controller_;
  flagella::LcmChannels channels_;
  ControllerInputs inputs_;
  ControllerOutputs last_;
  PendingFix fix_;  ///< the latest camera fix not yet given to the controller
  long imu_received_ = 0, commands_published_ = 0, camera_received_ = 0;
};

}  // namespace flagella::control
