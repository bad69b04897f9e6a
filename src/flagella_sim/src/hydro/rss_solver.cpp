#include "flagella_sim/hydro/rss_solver.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

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
  update(nodes, segments, eps, viscosity);
}

void RssSolver::update(const Polyline& nodes, const Segments& segments, double eps,
                       double viscosity) {
  mu_ = checkedViscosity(viscosity);
  eps_ = eps;
  assembleRssMatrix(nodes, segments, eps, ablk_);
  lengths_ = rss::voronoiLengths(nodes, segments);
  if (!lu_.factorize(ablk_))
    throw std::invalid_argument("the RSS matrix is singular (reciprocal condition " +
                                std::to_string(lu_.rcond()) +
                                "): nodes too close for this eps, or eps too small");
}

void RssSolver::checkSize(const VecX& velocities) const {
  if (velocities.size() != ablk_.rows()) {
    throw std::invalid_argument("velocities: expected 3 * nodes = " + std::to_string(ablk_.rows()) +
                                " entries, got " + std::to_string(velocities.size()));
  }
}

VecX RssSolver::forceDensities(const VecX& velocities) const {
  checkSize(velocities);
  return 8.0 * units::pi * mu_ * lu_.solve(velocities);  // docs/model.md 4.3
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
  return dragRowWeights().asDiagonal() * lu_.inverse();  // docs/model.md 4.4 option B
}

}  // namespace flagella::rss
