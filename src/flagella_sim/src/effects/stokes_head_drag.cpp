#include "flagella_sim/effects/stokes_head_drag.h"

#include <cmath>

namespace flagella {

StokesHeadDrag::StokesHeadDrag(double C_t, double C_r, double head_radius) : Effect(kName) {
  c_t_ = params_.declare("C_t", C_t, 0.0, 1e4, "", "head translational drag prefactor");
  c_r_ = params_.declare("C_r", C_r, 0.0, 1e4, "", "head rotational drag prefactor");
  radius_ = params_.declare("head_radius", head_radius, 1e-6, 10.0, "m", "head radius a");
}

void StokesHeadDrag::attach(const RodNetwork& net) {
  node_ = net.parts.head_center_node;
  theta_dof_ = net.thetaIndex(net.parts.head_edge);
}

void StokesHeadDrag::addForce(const EffectContext& ctx, VecX& force, JacobianSink* jacobian) const {
  const double mu = ctx.medium.viscosity();
  const double a = params_[radius_];
  const double trans = params_[c_t_] * 6.0 * M_PI * mu * a;             // spec 3.1
  const double rot = params_[c_r_] * 8.0 * M_PI * mu * std::pow(a, 3);  // spec 3.1
  force.segment<3>(3 * node_) -= trans * ctx.nodeVelocity(node_);
  force(theta_dof_) -= rot * ctx.rate(theta_dof_);
  if (!jacobian) return;
  jacobian->addBlock(3 * node_, 3 * node_, -(trans / ctx.dt) * Mat3::Identity());
  jacobian->add(theta_dof_, theta_dof_, -rot / ctx.dt);
}

}  // namespace flagella
