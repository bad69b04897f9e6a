// Global RSS matrix of a polyline (docs/model.md 4.3): 8 pi mu U = Ablk F for nodal velocities U
// and nodal force densities F (force per length exerted on the fluid).
#pragma once

#include <vector>

#include "flagella_sim/core/types.h"

namespace flagella::rss {

using Polyline = std::vector<Vec3>;

/// Throws std::invalid_argument (naming the field and the allowed range) unless eps is finite and
/// > 0, there are at least 2 nodes, all coordinates are finite and no segment has zero length.
void validatePolyline(const Polyline& nodes, double eps);

/// Dense 3M x 3M Ablk: Ablk[p, a] += Dl_j A1, Ablk[p, b] += Dl_j A2 for every node p and every
/// segment j = (a, a+1) (docs/model.md 4.3). Not symmetric in general (collocation).
MatX assembleRssMatrix(const Polyline& nodes, double eps);

/// Voronoi lengths l_p: half of each adjacent edge (half-edge at the two ends) (docs/model.md 4.3).
VecX voronoiLengths(const Polyline& nodes);

}  // namespace flagella::rss
