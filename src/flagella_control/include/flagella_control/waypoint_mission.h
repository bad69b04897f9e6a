// A 3-D waypoint mission for the mass-transformer controller (config/paths/*.yaml):
//
//   waypoints:
//     frame: start       # start: origin at the robot's start, x along its initial direction of
//                        #        travel (horizontal), y to its left, z up; world: output frame
//     tolerance: 0.018   # a waypoint is reached within this distance of the head centre [m]
//     points:            # visited in order [m]
//       - [0.02, 0.0, 0.01]
//       - [0.04, 0.01, 0.0]
//     description: "climb, dive, turn"   # optional
//     course_time: 30    # optional, start frame only: x along the course over the first
//                        # course_time seconds of straight, level cruise (the helical robot
//                        # does not swim along its head axis); 0 (default): the head axis at t = 0
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "flagella_control/path_spec.h"

namespace flagella::control {

struct WaypointMission {
  std::vector<Eigen::Vector3d> points;  ///< in the mission's frame [m]
  PathFrame frame = PathFrame::Start;
  double tolerance = 0.018;  ///< [m]
  double course_time = 0.0;  ///< [s]: the start frame's x from the course over this time
  std::string description;

  /// Throws std::invalid_argument naming the field and its allowed range.
  void validate() const;
};

/// Throws std::runtime_error naming the file and the field.
WaypointMission loadWaypointMission(const std::string& path);

/// A point of the mission in the world, for a start at `origin` with initial azimuth `azimuth`.
Eigen::Vector3d worldWaypoint(const WaypointMission& mission, const Eigen::Vector3d& point,
                              const Eigen::Vector3d& origin, double azimuth);

}  // namespace flagella::control
