#include "flagella_sim/effects/stokes_head_drag.h"

#include <cmath>

namespace flagella {

StokesHeadDrag::StokesHeadDrag(double C_t, double C_r, double head_radius, double tilt_drag)
    : Effect(kName, stokesHeadDragEffect().parameters) {
  c_t_ = parameterIndex("C_t", C_t);
  c_r_ = parameterIndex("C_r", C_r);
  radius_ = parameterIndex("head_radius", head_radius);
  tilt_ = parameterIndex("tilt_drag", tilt_drag);
}

const EffectDescriptor& stokesHeadDragEffect() {
  static const EffectDescriptor d = [] {
    EffectDescriptor e;
    e.name = StokesHeadDrag::kName;
    e.description = "Stokes drag and torque on the rigid head";
    e.parameters = {{"C_t", 1.0, 0.0, 1e4, "", "head translational drag prefactor"},
                    {"C_r", 1.0, 0.0, 1e4, "", "head rotational drag prefactor"},
                    {"head_radius", 0.02, 1e-6, 10.0, "m", "head radius a"},
                    {"tilt_drag", 0.0, 0.0, 100.0, "",
                     "rotational drag about the pitch and yaw axes as a multiple of the spin's "
                     "(1: a sphere, every axis alike; 0: spin only)"}};
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
  front_ = net.parts.head_front_node;
  back_ = net.parts.joint_node;
  theta_dof_ = net.thetaIndex(net.parts.head_edge);
}

void StokesHeadDrag::addForce(const EffectContext& ctx, VecX& force, JacobianSink* jacobian) const {
  const double mu = ctx.viscosity;
  const double a = params_[radius_];
  const double trans = params_[c_t_] * 6.0 * M_PI * mu * a;             // docs/model.md 3.1
  const double rot = params_[c_r_] * 8.0 * M_PI * mu * std::pow(a, 3);  // docs/model.md 3.1
  force.segment<3>(3 * node_) -= trans * ctx.nodeVelocity(node_);
  force(theta_dof_) -= rot * ctx.rate(theta_dof_);
  if (jacobian) {
    jacobian->addBlock(3 * node_, 3 * node_, -(trans / ctx.dt) * Mat3::Identity());
    jacobian->add(theta_dof_, theta_dof_, -rot / ctx.dt);
  }
  addTiltDrag(ctx, params_[tilt_] * rot, force, jacobian);
}

// docs/model.md 3.1: the couple -k u x (w_perp)/d on x_2 and x_0 (w = v_2 - v_0, u and d = |x_2 -
// x_0| frozen at t_k) is the torque -k Omega_perp about x_1, Omega_perp = u x w / d.
void StokesHeadDrag::addTiltDrag(const EffectContext& ctx, double k, VecX& force,
                                 JacobianSink* jacobian) const {
  const Vec3 axis = ctx.q_start.segment<3>(3 * back_) - ctx.q_start.segment<3>(3 * front_);
  const double d = axis.norm();
  const Vec3 u = axis / d;
  const Mat3 damping = (k / (d * d)) * (Mat3::Identity() - u * u.transpose());
  const Vec3 f_back = -damping * (ctx.nodeVelocity(back_) - ctx.nodeVelocity(front_));
  force.segment<3>(3 * back_) += f_back;
  force.segment<3>(3 * front_) -= f_back;
  if (!jacobian) return;  // entries added whatever k is: the pattern does not depend on values
  const Mat3 block = damping / ctx.dt;
  jacobian->addBlock(3 * back_, 3 * back_, -block);
  jacobian->addBlock(3 * back_, 3 * front_, block);
  jacobian->addBlock(3 * front_, 3 * back_, block);
  jacobian->addBlock(3 * front_, 3 * front_, -block);
}

}  // namespace flagella
