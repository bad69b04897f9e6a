#include "flagella_sim/hydro/rss_matrix.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "flagella_sim/hydro/segment_integrals.h"

namespace flagella::rss {

void validatePolyline(const Polyline& nodes, double eps) {
  if (!(std::isfinite(eps) && eps > 0.0)) {
    std::ostringstream msg;
    msg << "eps (regularization) must be finite and > 0, got " << eps;
    throw std::invalid_argument(msg.str());
  }
  if (nodes.size() < 2) {
    throw std::invalid_argument("nodes: need at least 2 nodes (1 segment), got " +
                                std::to_string(nodes.size()));
  }
  for (std::size_t p = 0; p < nodes.size(); ++p) {
    if (!nodes[p].allFinite()) {
      throw std::invalid_argument("nodes: node " + std::to_string(p) +
                                  " has a non-finite coordinate");
    }
    if (p > 0 && !((nodes[p] - nodes[p - 1]).norm() > 0.0)) {
      throw std::invalid_argument("nodes: segment " + std::to_string(p - 1) +
                                  " has zero length (edge lengths must be > 0)");
    }
  }
}

MatX assembleRssMatrix(const Polyline& nodes, double eps) {
  validatePolyline(nodes, eps);
  const int m = static_cast<int>(nodes.size());
  MatX ablk = MatX::Zero(3 * m, 3 * m);
  for (int p = 0; p < m; ++p) {
    for (int a = 0; a + 1 < m; ++a) {
      const SegmentBlocks b = segmentBlocks(nodes[p], nodes[a], nodes[a + 1], eps);
      const double dl = (nodes[a + 1] - nodes[a]).norm();
      ablk.block<3, 3>(3 * p, 3 * a) += dl * b.a1;  // docs/model.md 4.3
      ablk.block<3, 3>(3 * p, 3 * (a + 1)) += dl * b.a2;
    }
  }
  return ablk;
}

VecX voronoiLengths(const Polyline& nodes) {
  const int m = static_cast<int>(nodes.size());
  VecX l = VecX::Zero(m);
  for (int a = 0; a + 1 < m; ++a) {
    const double half = 0.5 * (nodes[a + 1] - nodes[a]).norm();
    l[a] += half;
    l[a + 1] += half;
  }
  return l;
}

}  // namespace flagella::rss
