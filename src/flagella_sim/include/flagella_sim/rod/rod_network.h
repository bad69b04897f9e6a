// Topology, material and rest state of a discrete-elastic-rod network (spec section 1).
// DOF layout (block ordering, docs/model.md 0): q = [x_0 .. x_{N-1}, theta^0 .. theta^{Ne-1}].
#pragma once

#include <string>
#include <vector>

#include "flagella_sim/core/types.h"

namespace flagella {

/// An edge stored with a fixed orientation, from its start node to its end node.
struct EdgeDef {
  int start_node = 0;
  int end_node = 0;
};

/// One stretching spring per edge (docs/model.md 1.2, 1.4).
struct StretchSpring {
  int edge = 0;
  double EA = 0.0;           ///< axial stiffness E*pi*r0^2 [N]
  double rest_length = 0.0;  ///< |ebar| [m]
};

/// A bending-twisting spring on two edges E, F sharing node c (docs/model.md 1.2, 1.6).
/// Locally E points into c (x_p -> x_c) and F out of c (x_c -> x_q); sign_e / sign_f are the
/// orientation signs s_g of docs/model.md 1.6 (+1 if the stored edge already points that way).
struct BendTwistSpring {
  int edge_e = 0;
  int edge_f = 0;
  int sign_e = 1;
  int sign_f = 1;
  int node_p = 0;
  int node_c = 0;
  int node_q = 0;
  double EI = 0.0;              ///< bending stiffness [N m^2]
  double GJ = 0.0;              ///< twisting stiffness [N m^2]
  double voronoi_length = 0.0;  ///< l_c = (|ebar^E| + |ebar^F|)/2, undeformed (docs/model.md 1.4)
  double kappa_bar1 = 0.0;      ///< natural material curvatures (set at t = 0)
  double kappa_bar2 = 0.0;
  double tau_bar = 0.0;  ///< natural twist (time-varying for the motor spring, docs/model.md 1.9)
  /// Angle by which edge F's material frame is turned back about t_F before the curvature is
  /// taken: the motor's natural twist gained since t = 0, so that the averaged directors do not
  /// vanish when the head and shaft frames are half a turn apart (docs/model.md 1.9). 0 for
  /// every other spring.
  double frame_turn = 0.0;
};

/// Named groups of nodes and edges that outputs, effects and messages refer to.
struct RobotParts {
  int head_front_node = 0;   ///< x_0
  int head_center_node = 1;  ///< x_1 (Stokes drag acts here)
  int joint_node = 2;        ///< x_2 (shaft end, disc centre)
  int head_edge = 0;         ///< e^0 = x_0 -> x_1, theta^0 is the head spin
  int shaft_edge = 1;        ///< e^1 = x_1 -> x_2, theta^1 is the tail-side spin
  int motor_spring = -1;     ///< index of the actuated bending-twisting spring (at x_1)
  std::vector<std::vector<int>> tail_nodes;  ///< nodes of each tail, root (disc rim) first
  std::vector<std::vector<int>> tail_edges;  ///< edges of each tail, root first
  std::vector<int> head_nodes;               ///< nodes of the rigid head, shaft and disc
};

/// The constant description of a rod network: everything except the evolving state.
struct RodNetwork {
  std::vector<Vec3> rest_positions;  ///< undeformed node positions at t = 0
  std::vector<EdgeDef> edges;
  std::vector<double> rest_lengths;  ///< |ebar^j| per edge
  std::vector<double> edge_radius;   ///< r0 per edge (used for inertia)
  std::vector<StretchSpring> stretch_springs;
  std::vector<BendTwistSpring> bend_twist_springs;
  VecX lumped_mass;             ///< diagonal mass matrix, ndof entries (docs/model.md 1.8)
  std::vector<bool> fixed_dof;  ///< Dirichlet-fixed DOFs (clamps, gimbal), ndof entries
  RobotParts parts;

  int numNodes() const { return static_cast<int>(rest_positions.size()); }
  int numEdges() const { return static_cast<int>(edges.size()); }
  int ndof() const { return 3 * numNodes() + numEdges(); }
  int thetaIndex(int edge) const { return 3 * numNodes() + edge; }
  static int positionIndex(int node) { return 3 * node; }

  /// Rest-state DOF vector (positions from rest_positions, all theta = 0).
  VecX restDofs() const;
};

/// Reads node i's position from a DOF vector.
inline Vec3 nodePosition(const VecX& q, int node) { return q.segment<3>(3 * node); }

}  // namespace flagella
