// Robustness of the mass-transformer closed loop (docs/model.md 7.4): a mission, or a set of
// them, over seeded runs whose model is wrong by +-`error` in each of eps, E, C_t, C_r and l_0
// (signs drawn per seed, the same for every mission) with noisy sensors, against the open-loop
// schedule the controller gave on the nominal model with perfect sensors, replayed blind on the
// same wrong models. Nominal runs (noise only) are reported beside them.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "flagella_control/steering_run.h"
#include "flagella_control/waypoint_mission.h"

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
  /// Also replay each mission's nominal schedule blind on every wrong model (one reference run
  /// per mission first, on the nominal model with perfect sensors); false: closed loops only.
  bool replay = true;
  /// Throws std::invalid_argument naming the field and its range.
  void validate() const;
};

/// One mission of a robustness set: its name (the waypoint file's stem) and its waypoints.
struct NamedMission {
  std::string name;
  WaypointMission mission;
};

struct RobustnessRun {
  std::string kind;         ///< "nominal closed", "mismatched closed", "mismatched open"
  std::size_t mission = 0;  ///< index into RobustnessReport::missions
  unsigned seed = 0;
  std::vector<std::pair<std::string, double>> factors;  ///< model errors (empty: nominal)
  SteeringRunResult result;
  std::string error;  ///< set if the run could not be made
};

struct RobustnessReport {
  std::vector<std::string> missions;  ///< names, in the order given
  std::vector<double> tolerances;     ///< [m] per mission
  /// Per mission, the nominal model with perfect sensors: the open-loop schedule's run (empty
  /// when RobustnessOptions::replay is off).
  std::vector<SteeringRunResult> references;
  std::vector<RobustnessRun> runs;
  double wall_seconds = 0.0;
};

/// The model errors of run `seed`: each key scaled by 1 + s error, s = +-1 drawn from the seed.
std::vector<std::pair<std::string, double>> drawModelErrors(const RobustnessOptions& options,
                                                            unsigned seed);

/// Runs everything (`jobs` threads): the references first, then every mission's runs together;
/// `progress` (optional) gets one line per finished run.
RobustnessReport runRobustness(const RobustnessOptions& options,
                               const SteeringCalibration& calibration,
                               const std::vector<NamedMission>& missions,
                               const SteeringGains& gains,
                               const std::function<void(const std::string&)>& progress = {});
/// The same for one mission (named "mission").
RobustnessReport runRobustness(const RobustnessOptions& options,
                               const SteeringCalibration& calibration,
                               const WaypointMission& mission, const SteeringGains& gains,
                               const std::function<void(const std::string&)>& progress = {});

/// Success rate and miss distances per kind, as a printed table; with several missions also per
/// mission and kind, and the missions passed per seed.
std::string robustnessSummary(const RobustnessReport& report);
/// Every run as JSON.
std::string robustnessJson(const RobustnessReport& report);

}  // namespace flagella::control
