// Path descriptions in YAML (config/paths/*.yaml) and their conversion to a Path.
//
//   path:
//     shape: rectangle    # polyline | circle | rectangle | triangle
//     frame: start        # start: relative to the robot's start (origin at the head, x along
//                         #        its direction of advance); world: absolute output-frame metres
//     width: 0.3          # rectangle [m] (first side, along x)
//     height: 0.3         # rectangle [m]
//     side: 0.3           # triangle (equilateral) [m]
//     radius: 0.2         # circle [m]
//     turn: left          # rectangle/triangle/circle: which way the path turns (left = CCW)
//     points: [[0, 0], [0.3, 0], [0.3, 0.2]]   # polyline [m]
//     closed: false       # polyline
//     laps: 1             # closed shapes: how many times to go round
//
// Every shape starts at its local origin heading along +x.
#pragma once

#include <string>

#include "flagella_control/path.h"

namespace YAML {
class Node;
}

namespace flagella::control {

enum class PathFrame { Start, World };

struct PathSpec {
  Path path;  ///< in the spec's own frame
  PathFrame frame = PathFrame::Start;
  int laps = 1;
  std::string description;  ///< e.g. "rectangle 0.3 x 0.3 m, left"
};

/// Throws std::runtime_error naming the field and its allowed range/values.
PathSpec pathSpecFromYaml(const YAML::Node& path_node);
PathSpec loadPathSpec(const std::string& file);

}  // namespace flagella::control
