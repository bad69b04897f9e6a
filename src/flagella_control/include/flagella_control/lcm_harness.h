// Headless harness: the core simulator and a controller core talk over LCM only (no ROS
// master). The simulator side (flagella::SimLcmShell, flagella_sim/lcm_io/sim_lcm_shell.h)
// publishes the rod state, the IMU and the camera fixes and applies motor commands; the
// controller side (ControllerLcmShell) steps the controller on every IMU sample (with the latest
// camera fix, once) and publishes its commands.
// With the default memq:// provider everything stays inside the process.
#pragma once

#include <functional>
#include <lcm/lcm-cpp.hpp>
#include <map>
#include <string>

#include "flagella_control/controller_core.h"
#include "flagella_control/controller_lcm_shell.h"
#include "flagella_sim/lcm_io/lcm_messages.h"
#include "flagella_sim/lcm_io/sim_lcm_shell.h"
#include "flagella_sim/runtime/sim_session.h"

namespace flagella::control {

/// The simulator shell's options (channel prefix, state rate, frames) plus the LCM provider.
struct HarnessOptions : flagella::SimLcmOptions {
  std::string lcm_url = "memq://";  ///< never default multicast in tests
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
  flagella::SimLcmShell sim_shell_;
  ControllerLcmShell controller_shell_;
};

}  // namespace flagella::control
