// Builds a path-following controller core from its mode name and gains (ROS node and CLI alike).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "flagella_control/path_controllers.h"
#include "flagella_control/receding_horizon_controller.h"

namespace flagella::control {

/// The known modes, the default first: receding_horizon (RecedingHorizonController),
/// closed_loop (PathFollowingController), open_loop (ScheduleController).
const std::vector<std::string>& pathControllerModes();

/// Throws std::invalid_argument "<field> must be 'receding_horizon', 'closed_loop' or
/// 'open_loop', got '<mode>'" unless `mode` is one of pathControllerModes().
void requirePathControllerMode(const std::string& mode, const std::string& field = "mode");

/// What selects and tunes a path-following controller (plain values; the ROS node fills it from
/// its private parameters, flagella_follow_path from its arguments).
struct PathControllerOptions {
  std::string mode = "receding_horizon";  ///< one of pathControllerModes()
  PathFollowingGains gains;               ///< closed_loop, and receding_horizon's fallback
  RecedingHorizonGains horizon_gains;     ///< receding_horizon
};

/// The controller of `options.mode` for `spec`. The receding-horizon controller plans the path
/// here (a few seconds). Throws std::invalid_argument for an unknown mode (requirePathController-
/// Mode) and whatever the controller's constructor throws (its gains are checked there; open_loop
/// uses none).
std::unique_ptr<PathControllerBase> makePathController(PathSpec spec, BinaryCalibration calibration,
                                                       const PathControllerOptions& options);

}  // namespace flagella::control
