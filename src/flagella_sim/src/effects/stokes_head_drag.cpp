#include "flagella_sim/effects/stokes_head_drag.h"

#include <cmath>

namespace flagella {

StokesHeadDrag::StokesHeadDrag(double C_t, double C_r, double head_radius)
    : Effect(kName, stokesHeadDragEffect().parameters) {
  c_t_ = parameterIndex("C_t", C_t);
  c_r_ = parameterIndex("C_r", C_r);
  radius_ = parameterIndex("head_radius", head_radius);
}

const EffectDescriptor& stokesHeadDragEffect() {
  static const EffectDescriptor d = [] {
    EffectDescriptor e;
    e.name = StokesHeadDrag::kName;
    e.description = "Stokes drag and torque on the rigid head";
    e.parameters = {{"C_t", 1.0, 0.0, 1e4, "", "head translational drag prefactor"},
                    {"C_r", 1.0, 0.0, 1e4, "", "head rotational drag prefactor"},
                    {"head_radius", 0.02, 1e-6, 10.0, "m", "head radius a"}};
    e.default_rules = {{"head_radius", "robot.head_radius"}};
    e.make = [](const EffectBuildContext& c) {
      return std::make_unique<StokesHeadDrag>(1.0, 1.0, c.robot.head_radius);
    };
    return e;
  }();
  return d;
}

void StokesHeadDrag::attach(const RodNetwork& net) {
  node_ = net.parts.head_center_node;
  theta_dof_ = net.thetaIndex(net.parts.head_edge);
}

void StokesHeadDrag::addForce(const EffectContext& ctx, VecX& force, JacobianSink* jacobian) const {
  const double mu = ctx.viscosity;
  const double a = params_[radius_];
  const double trans = params_[c_t_] * 6.0 * M_PI * mu * a;             // docs/model.md 3.1
  const double rot = params_[c_r_] * 8.0 * M_PI * mu * std::pow(a, 3);  // docs/model.md 3.1
  force.segment<3>(3 * node_) -= trans * ctx.nodeVelocity(node_);
  force(theta_dof_) -= rot * ctx.rate(theta_dof_);
  if (!jacobian) return;
  jacobian->addBlock(3 * node_, 3 * node_, -(trans / ctx.dt) * Mat3::Identity());
  jacobian->add(theta_dof_, theta_dof_, -rot / ctx.dt);
}

}  // namespace flagella
