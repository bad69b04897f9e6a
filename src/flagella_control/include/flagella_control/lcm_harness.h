// Headless harness: the core simulator and a controller core talk over LCM only (no ROS
// master). The simulator side publishes the rod state, the IMU and the camera fixes and applies
// motor commands; the controller side steps the controller on every IMU sample (with the latest
// camera fix, once) and publishes its commands.
// With the default memq:// provider everything stays inside the process.
#pragma once

#include <flagella_lcm/controller_status_t.hpp>
#include <flagella_lcm/imu_t.hpp>
#include <flagella_lcm/motor_command_t.hpp>
#include <flagella_lcm/point_stamped_t.hpp>
#include <flagella_lcm/rod_state_t.hpp>
#include <flagella_lcm/slider_command_t.hpp>
#include <functional>
#include <lcm/lcm-cpp.hpp>
#include <map>
#include <string>

#include "flagella_control/controller_core.h"
#include "flagella_sim/lcm_io/lcm_messages.h"
#include "flagella_sim/runtime/rate_schedule.h"
#include "flagella_sim/runtime/sim_session.h"

namespace flagella_control {

using flagella::LcmChannels;

struct HarnessOptions {
  std::string lcm_url = "memq://";  ///< never default multicast in tests
  std::string channel_prefix = "FLAGELLA_";
  double state_rate = 20.0;  ///< rod state and controller status [Hz of sim time]
  std::string world_frame = "world";
  std::string imu_frame = "head";
};

/// Messages published and received per channel, and the time spent.
struct HarnessReport {
  double sim_time = 0.0;
  double wall_seconds = 0.0;
  long steps = 0;
  bool halted = false;
  std::map<std::string, long> published;
  std::map<std::string, long> received;
};

/// The simulator's end of the LCM link.
class SimLcmShell {
 public:
  SimLcmShell(lcm::LCM& lcm, flagella::SimSession& session, const HarnessOptions& options);
  /// Publishes whatever is due at the session's current time.
  void publishDue(HarnessReport& report, bool force = false);

 private:
  void onMotorCommand(const lcm::ReceiveBuffer*, const std::string&,
                      const flagella_lcm::motor_command_t* msg);
  void onSliderCommand(const lcm::ReceiveBuffer*, const std::string&,
                       const flagella_lcm::slider_command_t* msg);

  lcm::LCM& lcm_;
  flagella::SimSession& session_;
  HarnessOptions options_;
  LcmChannels channels_;
  flagella::RateSchedule state_schedule_, imu_schedule_, camera_schedule_;
  long motor_received_ = 0, slider_received_ = 0;
  friend class LcmHarness;
};

/// The controller's end: steps the core on every IMU sample, publishes the motor command. A
/// camera fix is handed to the controller on the next step only (position_valid), then dropped.
class ControllerLcmShell {
 public:
  ControllerLcmShell(lcm::LCM& lcm, ControllerCore& controller, const HarnessOptions& options);
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
  HarnessOptions options_;
  LcmChannels channels_;
  ControllerInputs inputs_;
  ControllerOutputs last_;
  bool fix_pending_ = false;
  double fix_position_[2] = {0.0, 0.0};  ///< latest camera fix not yet given to the controller
  long imu_received_ = 0, commands_published_ = 0, camera_received_ = 0;
};

class LcmHarness {
 public:
  /// Throws std::runtime_error if the LCM provider cannot be opened.
  LcmHarness(flagella::SimSession& session, ControllerCore& controller, HarnessOptions options);
  /// Steps the session for `duration` seconds of simulated time, delivering every message
  /// after each step. `after_step` (optional) sees the session after each step.
  HarnessReport run(double duration, const std::function<void()>& after_step = {});
  /// Ends the current run() after the step in progress (call from `after_step`).
  void requestStop() { stop_requested_ = true; }

 private:
  void deliverAll();
  bool stop_requested_ = false;

  HarnessOptions options_;
  lcm::LCM lcm_;
  flagella::SimSession& session_;
  SimLcmShell sim_shell_;
  ControllerLcmShell controller_shell_;
};

}  // namespace flagella_control
