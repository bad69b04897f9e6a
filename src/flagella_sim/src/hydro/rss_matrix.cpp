#include "flagella_sim/hydro/rss_matrix.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "flagella_sim/hydro/segment_integrals.h"

namespace flagella::rss {

Segments chainSegments(int node_count) {
  Segments segments;
  for (int a = 0; a + 1 < node_count; ++a) segments.push_back({a, a + 1});
  return segments;
}

void validatePolyline(const Polyline& nodes, const Segments& segments, double eps) {
  if (!(std::isfinite(eps) && eps > 0.0)) {
    std::ostringstream msg;
    msg << "eps (regularization) must be finite and > 0, got " << eps;
    throw std::invalid_argument(msg.str());
  }
  if (nodes.size() < 2 || segments.empty()) {
    throw std::invalid_argument("nodes: need at least 2 nodes (1 segment), got " +
                                std::to_string(nodes.size()));
  }
  for (std::size_t p = 0; p < nodes.size(); ++p)
    if (!nodes[p].allFinite())
      throw std::invalid_argument("nodes: node " + std::to_string(p) +
                                  " has a non-finite coordinate");
  const int m = static_cast<int>(nodes.size());
  for (std::size_t j = 0; j < segments.size(); ++j) {
    const auto [a, b] = segments[j];
    if (a < 0 || b < 0 || a >= m || b >= m)
      throw std::invalid_argument("segments: segment " + std::to_string(j) +
                                  " names a node outside [0, " + std::to_string(m - 1) + "]");
    if (!((nodes[b] - nodes[a]).norm() > 0.0))
      throw std::invalid_argument("nodes: segment " + std::to_string(j) +
                                  " has zero length (edge lengths must be > 0)");
  }
}

void validatePolyline(const Polyline& nodes, double eps) {
  validatePolyline(nodes, chainSegments(static_cast<int>(nodes.size())), eps);
}

MatX assembleRssMatrix(const Polyline& nodes, const Segments& segments, double eps) {
  MatX ablk;
  assembleRssMatrix(nodes, segments, eps, ablk);
  return ablk;
}

void assembleRssMatrix(const Polyline& nodes, const Segments& segments, double eps, MatX& ablk) {
  validatePolyline(nodes, segments, eps);
  const int m = static_cast<int>(nodes.size());
  ablk.setZero(3 * m, 3 * m);
  for (const auto& [a, b] : segments) {
    const double dl = (nodes[b] - nodes[a]).norm();
    for (int p = 0; p < m; ++p) {
      const SegmentBlocks blocks = segmentBlocks(nodes[p], nodes[a], nodes[b], eps);
      ablk.block<3, 3>(3 * p, 3 * a) += dl * blocks.a1;  // docs/model.md 4.3
      ablk.block<3, 3>(3 * p, 3 * b) += dl * blocks.a2;
    }
  }
}

MatX assembleRssMatrix(const Polyline& nodes, double eps) {
  return assembleRssMatrix(nodes, chainSegments(static_cast<int>(nodes.size())), eps);
}

VecX voronoiLengths(const Polyline& nodes, const Segments& segments) {
  VecX l = VecX::Zero(static_cast<int>(nodes.size()));
  for (const auto& [a, b] : segments) {
    const double half = 0.5 * (nodes[b] - nodes[a]).norm();
    l[a] += half;
    l[b] += half;
  }
  return l;
}

VecX voronoiLengths(const Polyline& nodes) {
  return voronoiLengths(nodes, chainSegments(static_cast<int>(nodes.size())));
}

}  // namespace flagella::rss
