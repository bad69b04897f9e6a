// The helical robot the suite's discovery and calibration tests use:
// config/identification/helical_shore32_coarse.yaml on edges of 30 mm instead of its 15 mm (about
// four per turn of the helix). Truth and model share the discretisation, so what the tests check
// (which effect is named) does not depend on it; the bench runs the same cases on the config's own
// edges. Measured on 2026-11-30 alone on the 2-core machine: test_discovery_helical 75 s instead of
// 267 s, test_discovery_helical_track 28 s instead of about 60 s, with the same verdicts.
#pragma once

#include <string>

#include "flagella_identify/model.h"

namespace flagella {
namespace identify {
namespace testing {

inline std::string helicalBaselinePath() {
  return FLAGELLA_CONFIG_DIR "/identification/helical_shore32_coarse.yaml";
}

/// The override that makes a helical config the suite's fast helix (edges of 30 mm).
inline std::string fastHelixEdges() { return "robot.edge_length=0.03"; }

inline YAML::Node fastHelicalBaseline() {
  return loadConfigTree(helicalBaselinePath(), {fastHelixEdges()});
}

}  // namespace testing
}  // namespace identify
}  // namespace flagella
