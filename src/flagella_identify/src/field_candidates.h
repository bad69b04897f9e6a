// Candidates that are not effects of the registry but fitted ratios of robot or effect fields
// of the baseline (candidates.cpp lists them after the effects).
#pragma once

#include <memory>
#include <string>

#include "flagella_identify/candidates.h"
#include "flagella_sim/robots/robot_model.h"

namespace flagella {
namespace identify {

/// The robot of a config as its type's parser reads the section `robot` (defaults included).
std::shared_ptr<RobotModel> robotOf(const YAML::Node& config);

/// A fit variable over [lower, upper], started at the geometric (log scale) or arithmetic mean.
FitParameter fitVariable(const std::string& name, const std::string& unit, double lower,
                         double upper, bool log_scale);

/// The hook of a helical flagellum stiffer or softer than the filament: the ratio multiplies
/// robot.hook_stiffness_scale (docs/model.md 8.4.1).
Candidate hookStiffnessCandidate();

/// The head's pitch and yaw drag other than the config's: the ratio multiplies
/// effects.stokes_head.tilt_drag (docs/model.md 3.1).
Candidate headTiltDragCandidate();

}  // namespace identify
}  // namespace flagella
