// Tilt of the helical flagellum against the head axis (docs/model.md 8.4.4): the principal axis
// of the helix's centre line, the buckling indicator of the summary.
#pragma once

#include <vector>

#include "flagella_sim/core/types.h"

namespace flagella {

/// Unit eigenvector of the largest eigenvalue of the points' covariance matrix, its sign chosen
/// so that it has a non-negative component along `reference`. Needs at least two points.
Vec3 principalAxis(const std::vector<Vec3>& points, const Vec3& reference);

/// Centre line of a helix given by nodes equally spaced in phi, `edges_per_turn` (not necessarily
/// an integer) edges per turn: the mean of the polyline over every one-turn window that starts at
/// a node. Points on the axis for an undeformed helix; empty if the nodes span less than a turn.
std::vector<Vec3> helixCentreLine(const std::vector<Vec3>& nodes, double edges_per_turn);

/// Angle [rad] between the head axis and the principal axis of the helix's centre line (of the
/// nodes themselves if they span less than about 1.05 turns); docs/model.md 8.4.4.
double flagellumTilt(const VecX& q, const std::vector<int>& helix_nodes, double edges_per_turn,
                     const Vec3& head_axis);

/// The same axis's part perpendicular to the head axis, in world coordinates: its norm is the
/// sine of flagellumTilt and it points where the flagellum leans (docs/model.md 8.4.4).
Vec3 flagellumTiltVector(const VecX& q, const std::vector<int>& helix_nodes, double edges_per_turn,
                         const Vec3& head_axis);

}  // namespace flagella
