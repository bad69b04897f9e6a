// The simulator's end of an LCM link, around a SimSession: publishes the rod state, the IMU and
// the camera fixes when they are due and applies the motor and slider commands it receives.
// The caller owns the LCM instance and delivers its messages (handle / handleTimeout).
#pragma once

#include <flagella_lcm/motor_command_t.hpp>
#include <flagella_lcm/slider_command_t.hpp>
#include <lcm/lcm-cpp.hpp>
#include <map>
#include <string>

#include "flagella_sim/lcm_io/lcm_messages.h"
#include "flagella_sim/runtime/output_schedule.h"
#include "flagella_sim/runtime/sim_session.h"

namespace flagella {

struct SimLcmOptions {
  std::string channel_prefix = "FLAGELLA_";
  double state_rate = 20.0;  ///< rod state and controller status [Hz of sim time]
  std::string world_frame = "world";
  std::string imu_frame = "head";
};

class SimLcmShell {
 public:
  SimLcmShell(lcm::LCM& lcm, SimSession& session, const SimLcmOptions& options);
  /// Publishes whatever is due at the session's current time (everything if `force`), counting
  /// each message under its channel in `published`.
  void publishDue(std::map<std::string, long>& published, bool force = false);
  long motorReceived() const { return motor_received_; }
  long sliderReceived() const { return slider_received_; }

 private:
  void onMotorCommand(const lcm::ReceiveBuffer*, const std::string&,
                      const flagella_lcm::motor_command_t* msg);
  void onSliderCommand(const lcm::ReceiveBuffer*, const std::string&,
                       const flagella_lcm::slider_command_t* msg);

  lcm::LCM& lcm_;
  SimSession& session_;
  SimLcmOptions options_;
  LcmChannels channels_;
  OutputSchedule schedule_;
  long motor_received_ = 0, slider_received_ = 0;
};

}  // namespace flagella
