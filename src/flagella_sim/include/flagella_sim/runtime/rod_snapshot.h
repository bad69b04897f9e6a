// A copy of everything a viewer or controller needs about the rod network at one instant, in
// the output frame (z up, REP-103), independent of any message library.
#pragma once

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "flagella_sim/core/types.h"

namespace flagella {

class Simulation;

struct RodSnapshot {
  double time = 0.0;
  std::string robot_name;
  std::vector<Vec3> nodes;                      ///< node positions [m]
  std::vector<int> edge_start, edge_end;        ///< edge j: edge_start[j] -> edge_end[j]
  std::vector<double> edge_twist;               ///< theta^j [rad]
  std::vector<Eigen::Quaterniond> edge_frames;  ///< material frame (m1, m2, t) of each edge
  std::vector<int> head_nodes;                  ///< rigid head, shaft and disc
  std::vector<std::vector<int>> tail_nodes;     ///< per tail, root first
  double omega_h = 0.0, omega_t = 0.0;          ///< signed spin rates [rad/s]
  double omega_motor = 0.0;                     ///< motor rate applied [rad/s]
  double head_angle = 0.0, tail_angle = 0.0;    ///< cumulative spin angles [rad]
  Vec3 head_position = Vec3::Zero();            ///< x_1
  Eigen::Quaterniond head_orientation = Eigen::Quaterniond::Identity();  ///< (m1^0, m2^0, t^0)

  /// True when every number in the snapshot is finite (nothing NaN is ever published).
  bool allFinite() const;
};

/// Rotation from the simulation's world frame (whatever its `up`) to the output frame, z up.
Eigen::Quaterniond outputFromSimulationFrame(const Vec3& up);

/// Copies the simulation's current state, rotated by `output_from_sim`.
RodSnapshot takeSnapshot(const Simulation& sim, const Eigen::Quaterniond& output_from_sim);

}  // namespace flagella
