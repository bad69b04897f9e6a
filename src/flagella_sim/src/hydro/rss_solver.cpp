#include "flagella_sim/hydro/rss_solver.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "flagella_sim/core/rigid_fit.h"
#include "flagella_sim/core/units.h"

namespace flagella::rss {
namespace {

double checkedViscosity(double mu) {
  if (!(std::isfinite(mu) && mu > 0.0)) {
    std::ostringstream msg;
    msg << "viscosity must be finite and > 0, got " << mu;
    throw std::invalid_argument(msg.str());
  }
  return mu;
}

}  // namespace

RssSolver::RssSolver(const Polyline& nodes, double eps, double viscosity)
    : RssSolver(nodes, chainSegments(static_cast<int>(nodes.size())), eps, viscosity) {}

RssSolver::RssSolver(const Polyline& nodes, const Segments& segments, double eps,
                     double viscosity) {
  lu_.estimateConditionOnlyIfPivotsSpread(true);  // rebuilt every buckled step (README, step cost)
  update(nodes, segments, eps, viscosity);
}

void RssSolver::update(const Polyline& nodes, const Segments& segments, double eps,
                       double viscosity) {
  mu_ = checkedViscosity(viscosity);
  eps_ = eps;
  rotated_ = false;
  rotated_matrix_valid_ = false;
  deviation_ = 0.0;
  factored_nodes_.clear();  // unusable for reuse until the build (and an eager LU) succeeds
  factored_ = false;
  assembleRssMatrix(nodes, segments, eps, ablk_);
  lengths_ = rss::voronoiLengths(nodes, segments);
  if (!lazy_) ensureFactored();
  factored_nodes_ = nodes;
  segments_ = segments;
}

void RssSolver::ensureFactored() const {
  if (factored_) return;
  if (!lu_.factorize(ablk_))
    throw std::invalid_argument("the RSS matrix is singular (reciprocal condition or pivot ratio " +
                                std::to_string(lu_.rcond()) +
                                "): nodes too close for this eps, or eps too small");
  factored_ = true;
}

bool RssSolver::updateOrReuse(const Polyline& nodes, const Segments& segments, double eps,
                              double viscosity, double tolerance) {
  RigidFit fit;
  bool reusable = tolerance > 0.0 && eps == eps_ && segments == segments_ &&
                  nodes.size() == factored_nodes_.size();
  if (reusable) {
    validatePolyline(nodes, segments, eps);
    fit = bestRigidFit(factored_nodes_, nodes);
    reusable = fit.deviation <= tolerance * eps;
  }
  if (!reusable) {
    update(nodes, segments, eps, viscosity);
    return false;
  }
  mu_ = checkedViscosity(viscosity);
  lengths_ = rss::voronoiLengths(nodes, segments);
  rotation_ = fit.rotation;
  rotated_ = true;
  rotated_matrix_valid_ = false;
  deviation_ = fit.deviation;
  return true;
}

const MatX& RssSolver::matrix() const {
  if (!rotated_) return ablk_;
  if (!rotated_matrix_valid_) {
    rotated_matrix_ = ablk_;
    rotateBlocks(rotated_matrix_);
    rotated_matrix_valid_ = true;
  }
  return rotated_matrix_;
}

MatX RssSolver::inverse() const {
  ensureFactored();
  MatX inv = lu_.inverse();
  if (rotated_) rotateBlocks(inv);
  return inv;
}

void RssSolver::rotateBlocks(MatX& m) const {
  // M -> Q M Q^T, 3x3 block by block (docs/model.md 4.4)
  const int n = nodeCount();
  for (int c = 0; c < n; ++c)
    for (int r = 0; r < n; ++r)
      m.block<3, 3>(3 * r, 3 * c) = rotation_ * m.block<3, 3>(3 * r, 3 * c) * rotation_.transpose();
}

VecX RssSolver::rotateEachNode(VecX v, bool inverse) const {
  for (int p = 0; p < nodeCount(); ++p)
    v.segment<3>(3 * p) = inverse ? Vec3(rotation_.transpose() * v.segment<3>(3 * p))
                                  : Vec3(rotation_ * v.segment<3>(3 * p));
  return v;
}

VecX RssSolver::multiply(const VecX& v) const {
  if (!rotated_ || rotated_matrix_valid_) return matrix() * v;
  // docs/model.md 4.4: Ablk(R y + c) v = Q Ablk(y) Q^T v, block by block
  return rotateEachNode(ablk_ * rotateEachNode(v, true), false);
}

VecX RssSolver::solveCurrent(const VecX& v) const {
  ensureFactored();
  if (!rotated_) return lu_.solve(v);
  return rotateEachNode(lu_.solve(rotateEachNode(v, true)), false);
}

void RssSolver::checkSize(const VecX& velocities) const {
  if (velocities.size() != ablk_.rows()) {
    throw std::invalid_argument("velocities: expected 3 * nodes = " + std::to_string(ablk_.rows()) +
                                " entries, got " + std::to_string(velocities.size()));
  }
}

VecX RssSolver::forceDensities(const VecX& velocities) const {
  checkSize(velocities);
  return 8.0 * units::pi * mu_ * solveCurrent(velocities);  // docs/model.md 4.3
}

VecX RssSolver::nodalForces(const VecX& velocities) const {
  VecX f = forceDensities(velocities);
  for (int p = 0; p < nodeCount(); ++p) f.segment<3>(3 * p) *= -lengths_[p];  // docs/model.md 4.3
  return f;
}

VecX RssSolver::dragRowWeights() const {
  VecX w(3 * nodeCount());
  for (int p = 0; p < nodeCount(); ++p)
    w.segment<3>(3 * p).setConstant(8.0 * units::pi * mu_ * lengths_[p]);  // docs/model.md 4.4
  return w;
}

MatX RssSolver::dragMatrix() const {
  return dragRowWeights().asDiagonal() * inverse();  // docs/model.md 4.4 option B
}

}  // namespace flagella::rss
