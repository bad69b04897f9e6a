// Global RSS matrix of a polyline (docs/model.md 4.3): 8 pi mu U = Ablk F for nodal velocities U
// and nodal force densities F (force per length exerted on the fluid).
#pragma once

#include <array>
#include <vector>

#include "flagella_sim/core/types.h"

namespace flagella::rss {

using Polyline = std::vector<Vec3>;
/// Segments as pairs of node indices (a, b): several chains (tails) share one system.
using Segments = std::vector<std::array<int, 2>>;

/// The segments (0,1), (1,2), ... of one chain of `node_count` nodes.
Segments chainSegments(int node_count);

/// Throws std::invalid_argument (naming the field and the allowed range) unless eps is finite and
/// > 0, there are at least 2 nodes, all coordinates are finite, every segment's indices are valid
/// and no segment has zero length.
void validatePolyline(const Polyline& nodes, const Segments& segments, double eps);
void validatePolyline(const Polyline& nodes, double eps);

/// Dense 3M x 3M Ablk: Ablk[p, a] += Dl_j A1, Ablk[p, b] += Dl_j A2 for every node p and every
/// segment j = (a, b) (docs/model.md 4.3). Not symmetric in general (collocation).
MatX assembleRssMatrix(const Polyline& nodes, const Segments& segments, double eps);
MatX assembleRssMatrix(const Polyline& nodes, double eps);
/// The same into `ablk` (resized; its storage is reused when the size is unchanged).
void assembleRssMatrix(const Polyline& nodes, const Segments& segments, double eps, MatX& ablk);

/// Voronoi lengths l_p: half of each adjacent segment (docs/model.md 4.3).
VecX voronoiLengths(const Polyline& nodes, const Segments& segments);
VecX voronoiLengths(const Polyline& nodes);

}  // namespace flagella::rss
