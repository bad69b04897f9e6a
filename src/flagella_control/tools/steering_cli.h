// What the steering tools (flagella_steer, flagella_steer_robustness) share on their command
// line: the robot config, the waypoint mission, the calibration, config overrides, the buckle
// schedule and controller gains, loading the mission, calibration and gains from them, and the
// parsing of name=number arguments (--gain, --model-error).
#pragma once

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "flagella_control/mass_transformer_controller.h"
#include "flagella_control/steering_calibration.h"
#include "flagella_control/steering_robustness.h"
#include "flagella_control/waypoint_mission.h"
#include "flagella_sim/core/parameter_set.h"
#include "flagella_sim/simulation/simulation_config.h"

namespace flagella::control::cli {

/// Splits an `option` argument `name=number` (`form` names the two parts for the message).
/// Throws flagella::ConfigError for a missing name or `=`, or a value that is not one finite
/// number.
inline std::pair<std::string, double> assignment(const std::string& text, const char* option,
                                                 const char* form) {
  const std::size_t eq = text.find('=');
  const std::string quoted = std::string(option) + " '" + text + "'";
  if (eq == std::string::npos || eq == 0)
    throw flagella::ConfigError(quoted + ": expected " + form);
  const std::string value = text.substr(eq + 1);
  std::size_t used = 0;
  double number = 0.0;
  try {
    number = std::stod(value, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != value.size() || !std::isfinite(number))
    throw flagella::ConfigError(quoted + ": the value is not a finite number");
  return {text.substr(0, eq), number};
}

struct SteeringInputs {
  std::string config_path, waypoints_path, calibration_path;
  std::vector<std::string> waypoints_paths;  ///< addTo(app, true): one or more missions
  std::vector<std::string> overrides;
  std::string schedule = "relax";
  std::string gains_path;                  ///< YAML gains file (SteeringGains::load), if any
  std::vector<std::string> gain_settings;  ///< name=value

  /// Registers --config, --waypoints, --calibration, --set and --schedule on `app`; with
  /// `several_missions`, --waypoints takes one or more files (missions()).
  void addTo(CLI::App& app, bool several_missions = false) {
    app.add_option("--config", config_path, "robot config YAML with a slider: section")
        ->required()
        ->check(CLI::ExistingFile);
    if (several_missions)
      app.add_option("--waypoints", waypoints_paths,
                     "waypoint YAML (config/paths); several files: a mission set, each run on "
                     "every seed")
          ->required()
          ->check(CLI::ExistingFile);
    else
      app.add_option("--waypoints", waypoints_path, "waypoint YAML (config/paths)")
          ->required()
          ->check(CLI::ExistingFile);
    app.add_option("--calibration", calibration_path,
                   "steering calibration YAML (flagella_steer_calibrate)")
        ->required()
        ->check(CLI::ExistingFile);
    app.add_option("--set", overrides, "config override a.b=value (repeatable)");
    app.add_option("--schedule", schedule, "buckle schedule: relax or three_level")
        ->capture_default_str()
        ->check(CLI::IsMember({"relax", "three_level"}));
    app.add_option("--gains", gains_path,
                   "controller gains YAML (steering_gains: name: value; e.g. "
                   "config/calibration/helical_steering_source_gains.yaml), before any --gain")
        ->check(CLI::ExistingFile);
    app.add_option("--gain", gain_settings,
                   "controller gain name=value (repeatable; --list-gains prints every gain with "
                   "its default, unit and meaning; e.g. max_steer_offset=8e-5)");
    app.add_flag_callback(
        "--list-gains",
        [] {
          std::fputs(SteeringGains().table().c_str(), stdout);
          throw CLI::Success();
        },
        "print every controller gain with its default, unit and meaning, and exit");
  }
  /// The input files, loaded; one that cannot be read as its kind throws InputFileError (exit 2).
  SteeringCalibration calibration() const { return loadSteeringCalibration(calibration_path); }
  WaypointMission mission() const { return loadWaypointMission(waypoints_path); }
  /// The missions of addTo(app, true), each named by its file's stem (by its path when two
  /// stems coincide).
  std::vector<NamedMission> missions() const {
    std::vector<NamedMission> out;
    for (const std::string& path : waypoints_paths) {
      const std::string stem = std::filesystem::path(path).stem().string();
      const bool shared = std::count_if(waypoints_paths.begin(), waypoints_paths.end(),
                                        [&](const std::string& other) {
                                          return std::filesystem::path(other).stem() == stem;
                                        }) > 1;
      out.push_back({shared ? path : stem, loadWaypointMission(path)});
    }
    return out;
  }
  /// The robot config with the overrides; refused without a slider (the mass-transformer).
  flagella::SimulationConfig config(const std::vector<std::string>& with_overrides) const {
    flagella::SimulationConfig c = flagella::loadSimulationConfig(config_path, with_overrides);
    if (!c.slider.enabled)
      throw flagella::ConfigError(config_path +
                                  ": the steering needs a robot with a slider: section (the "
                                  "mass-transformer), as config/helical_steering.yaml");
    return c;
  }
  /// The default gains with the chosen schedule, the --gains file and the --gain settings
  /// (validated).
  SteeringGains gains() const {
    SteeringGains g;
    g.schedule = scheduleFromName(schedule);
    if (!gains_path.empty()) g.load(gains_path);
    for (const std::string& setting : gain_settings) {
      const auto [name, value] = assignment(setting, "--gain", "name=value");
      g.set(name, value);
    }
    g.validate();
    return g;
  }
};

}  // namespace flagella::control::cli
