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

namespace {

// Dl A1 and Dl A2 of docs/model.md 4.2 added at rows `row`, columns `col_a` and `col_b` (4.3):
// both are symmetric, so six distinct entries each.
void addSegmentBlocks(const Vec3& r, const SegmentGeometry& segment, const SegmentIntegrals& t,
                      double eps, MatX& ablk, int row, int col_a, int col_b) {
  const Vec3& v = segment.v;
  const SegmentBlockCoefficients c = segmentBlockCoefficients(t, eps, segment.dl);
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i <= j; ++i) {
      const double rr = r[i] * r[j], rv = r[i] * v[j] + v[i] * r[j], vv = v[i] * v[j];
      const double diagonal = i == j ? 1.0 : 0.0;
      const double a1 = c.d1 * diagonal + c.rr1 * rr + c.rv1 * rv + c.vv1 * vv;
      const double a2 = c.d2 * diagonal + c.rr2 * rr + c.rv2 * rv + c.vv2 * vv;
      ablk(row + i, col_a + j) += a1;
      ablk(row + i, col_b + j) += a2;
      if (i != j) {
        ablk(row + j, col_a + i) += a1;
        ablk(row + j, col_b + i) += a2;
      }
    }
}

}  // namespace

MatX assembleRssMatrix(const Polyline& nodes, const Segments& segments, double eps) {
  MatX ablk;
  assembleRssMatrix(nodes, segments, eps, ablk);
  return ablk;
}

void assembleRssMatrix(const Polyline& nodes, const Segments& segments, double eps, MatX& ablk) {
  validatePolyline(nodes, segments, eps);
  const int m = static_cast<int>(nodes.size());
  ablk.setZero(3 * m, 3 * m);
  // R = sqrt(|x_p - x_q|^2 + eps^2) of every node pair: each segment end's R_alpha (4.2), once
  const double e2 = eps * eps;
  MatX end_r(m, m);
  for (int q = 0; q < m; ++q)
    for (int p = 0; p <= q; ++p)
      end_r(p, q) = end_r(q, p) = std::sqrt((nodes[p] - nodes[q]).squaredNorm() + e2);
  for (const auto& [a, b] : segments) {
    const SegmentGeometry segment(nodes[a], nodes[b]);
    for (int p = 0; p < m; ++p) {
      const Vec3 r = nodes[p] - nodes[a];
      const SegmentIntegrals t = segmentIntegrals(r, segment, end_r(p, a), end_r(p, b), eps);
      addSegmentBlocks(r, segment, t, eps, ablk, 3 * p, 3 * a, 3 * b);
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
