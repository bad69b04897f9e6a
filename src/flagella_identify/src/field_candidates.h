// Candidates that are not effects of the registry but fitted ratios of robot or effect fields
// of the baseline (candidates.cpp lists them after the effects).
#pragma once

#include <string>

#include "flagella_identify/candidates.h"

namespace flagella {
namespace identify {

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
