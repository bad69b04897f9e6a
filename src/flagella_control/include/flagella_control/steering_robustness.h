// Robustness of the mass-transformer closed loop (docs/model.md 7.4): the same mission over
// seeded runs whose model is wrong by +-`error` in each of eps, E, C_t, C_r and l_0 (signs drawn
// per run) with noisy sensors, against the open-loop schedule the controller gave on the nominal
// model with perfect sensors, replayed blind on the same wrong models. Nominal runs (noise only)
// are reported beside them.
#pragma once

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "flagella_control/steering_run.h"

namespace flagella::control {

struct RobustnessOptions {
  std::string config_path;
  std::vector<std::string> overrides;  ///< applied to every run, before the model errors
  int runs = 10;
  double error = 0.2;  ///< relative model error of each key
  /// Model values made wrong: aliases eps, E, C_t, C_r, l_0, m_s (slider mass), k_t (the motor's
  /// torque constant: effects.dc_motor.stall_torque) or section.field paths.
  std::vector<std::string> keys = {"eps", "E", "C_t", "C_r", "l_0"};
  unsigned first_seed = 1;
  int jobs = 1;
  double max_duration = 600.0;  ///< [s] of simulated time per run
  bool nominal = true;          ///< also run the closed loop on the nominal model per seed
  /// Throws std::invalid_argument naming the field and its range.
  void validate() const;
};

struct RobustnessRun {
  std::string kind;  ///< "nominal closed", "mismatched closed", "mismatched open"
  unsigned seed = 0;
  std::vector<std::pair<std::string, double>> factors;  ///< model errors (empty: nominal)
  SteeringRunResult result;
  std::string error;  ///< set if the run could not be made
};

struct RobustnessReport {
  SteeringRunResult reference;  ///< nominal model, perfect sensors: the open-loop schedule
  std::vector<RobustnessRun> runs;
  double wall_seconds = 0.0;
};

/// The model errors of run `seed`: each key scaled by 1 + s error, s = +-1 drawn from the seed.
std::vector<std::pair<std::string, double>> drawModelErrors(const RobustnessOptions& options,
                                                            unsigned seed);

/// Runs everything (`jobs` threads); `progress` (optional) gets one line per finished run.
RobustnessReport runRobustness(const RobustnessOptions& options,
                               const SteeringCalibration& calibration,
                               const WaypointMission& mission, const SteeringGains& gains,
                               const std::function<void(const std::string&)>& progress = {});

/// Success rate and miss distances per kind, as a printed table.
std::string robustnessSummary(const RobustnessReport& report, double tolerance);
/// Every run as JSON.
std::string robustnessJson(const RobustnessReport& report, double tolerance);

}  // namespace flagella::control
