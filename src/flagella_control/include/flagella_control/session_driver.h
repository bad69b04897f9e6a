// A fresh simulator session driven step by step at a commanded motor rate (with the config's
// soft start), as the calibration runs use it; failures become std::runtime_error naming the run.
#pragma once

#include <string>

#include "flagella_sim/runtime/sim_session.h"

namespace flagella::control {

class SessionDriver {
 public:
  /// `max_omega`: the largest |rate| the run will command [rad/s].
  SessionDriver(const flagella::SimulationConfig& config, double max_omega, std::string run);
  /// One dt at `signed_omega` (scaled by the soft start during the first ramp_time); returns
  /// the rate applied [rad/s]. Its integral is the shaft angle a controller integrates from its
  /// own commands, which the simulator applies as they are (no soft start).
  double step(double signed_omega);
  /// Offers a slider position [m] (std::runtime_error if rejected).
  void commandSlider(double position);
  flagella::SimSession& session() { return session_; }
  const flagella::SimSession& session() const { return session_; }
  double dt() const { return session_.dt(); }
  double time() const { return session_.time(); }
  const std::string& run() const { return run_; }

 private:
  flagella::SimSession session_;
  double ramp_;
  std::string run_;
};

}  // namespace flagella::control
