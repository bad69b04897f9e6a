// What the steering tools (flagella_steer, flagella_steer_robustness) share on their command
// line: the robot config, the waypoint mission, the calibration, config overrides and the buckle
// schedule, and loading the mission, calibration and gains from them.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "flagella_control/mass_transformer_controller.h"
#include "flagella_control/steering_calibration.h"
#include "flagella_control/waypoint_mission.h"

namespace flagella::control::cli {

struct SteeringInputs {
  std::string config_path, waypoints_path, calibration_path;
  std::vector<std::string> overrides;
  std::string schedule = "relax";

  /// Registers --config, --waypoints, --calibration, --set and --schedule on `app`.
  void addTo(CLI::App& app) {
    app.add_option("--config", config_path, "robot config YAML with a slider: section")
        ->required()
        ->check(CLI::ExistingFile);
    app.add_option("--waypoints", waypoints_path, "waypoint YAML (config/paths)")
        ->required()
        ->check(CLI::ExistingFile);
    app.add_option("--calibration", calibration_path,
                   "steering calibration YAML (flagella_steer_calibrate)")
        ->required()
        ->check(CLI::ExistingFile);
    app.add_option("--set", overrides, "config override a.b=value (repeatable)");
    app.add_option("--schedule", schedule, "buckle schedule: relax or three_level")
        ->check(CLI::IsMember({"relax", "three_level"}));
  }
  SteeringCalibration calibration() const { return loadSteeringCalibration(calibration_path); }
  WaypointMission mission() const { return loadWaypointMission(waypoints_path); }
  /// The default gains with the chosen schedule.
  SteeringGains gains() const {
    SteeringGains g;
    g.schedule = scheduleFromName(schedule);
    return g;
  }
};

}  // namespace flagella::control::cli
