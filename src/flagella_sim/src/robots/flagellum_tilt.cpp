#include "flagella_sim/robots/flagellum_tilt.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <stdexcept>

#include "flagella_sim/core/geometry.h"
#include "flagella_sim/rod/rod_network.h"

namespace flagella {

namespace {

// Mean of the polyline through `nodes` over the index interval [start, start + length]
// (trapezoid rule on whole edges, exact integral of the last, partial edge).
Vec3 windowMean(const std::vector<Vec3>& nodes, size_t start, double length) {
  const size_t whole = static_cast<size_t>(std::floor(length));
  const double f = length - static_cast<double>(whole);
  Vec3 sum = Vec3::Zero();
  for (size_t k = start; k < start + whole; ++k) sum += 0.5 * (nodes[k] + nodes[k + 1]);
  const Vec3& a = nodes[start + whole];
  if (f > 0.0) sum += f * a + 0.5 * f * f * (nodes[start + whole + 1] - a);
  return sum / length;
}

}  // namespace

Vec3 principalAxis(const std::vector<Vec3>& points, const Vec3& reference) {
  if (points.size() < 2) throw std::invalid_argument("principalAxis needs at least two points");
  Vec3 mean = Vec3::Zero();
  for (const Vec3& p : points) mean += p;
  mean /= static_cast<double>(points.size());
  Mat3 covariance = Mat3::Zero();
  for (const Vec3& p : points) covariance += (p - mean) * (p - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Mat3> solver(covariance);
  const Vec3 axis = solver.eigenvectors().col(2);  // eigenvalues ascend
  return axis.dot(reference) < 0.0 ? Vec3(-axis) : axis;
}

std::vector<Vec3> helixCentreLine(const std::vector<Vec3>& nodes, double edges_per_turn) {
  if (!(edges_per_turn > 0.0)) throw std::invalid_argument("edges_per_turn must be > 0");
  std::vector<Vec3> centre;
  // a window [i, i + w] needs the nodes up to index i + floor(w) + 1
  const size_t needed = static_cast<size_t>(std::floor(edges_per_turn)) + 1;
  for (size_t i = 0; i + needed < nodes.size(); ++i)
    centre.push_back(windowMean(nodes, i, edges_per_turn));
  return centre;
}

namespace {

// Principal axis of the helix's centre line (of its nodes below about 1.05 turns), along t.
Vec3 helixAxis(const VecX& q, const std::vector<int>& helix_nodes, double edges_per_turn,
               const Vec3& t) {
  std::vector<Vec3> points;
  points.reserve(helix_nodes.size());
  for (int node : helix_nodes) points.push_back(nodePosition(q, node));
  const std::vector<Vec3> centre = helixCentreLine(points, edges_per_turn);
  return principalAxis(centre.size() >= 2 ? centre : points, t);
}

}  // namespace

double flagellumTilt(const VecX& q, const std::vector<int>& helix_nodes, double edges_per_turn,
                     const Vec3& head_axis) {
  const Vec3 t = head_axis.normalized();
  return angleBetween(t, helixAxis(q, helix_nodes, edges_per_turn, t));
}

Vec3 flagellumTiltVector(const VecX& q, const std::vector<int>& helix_nodes, double edges_per_turn,
                         const Vec3& head_axis) {
  const Vec3 t = head_axis.normalized();
  const Vec3 axis = helixAxis(q, helix_nodes, edges_per_turn, t);
  return axis - axis.dot(t) * t;
}

}  // namespace flagella
