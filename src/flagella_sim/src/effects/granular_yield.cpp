#include "flagella_sim/effects/granular_yield.h"

#include <cmath>

namespace flagella {

void addRegularizedCoulombForce(const EffectContext& ctx, int node, double yield_force,
                                double velocity_scale, VecX& force, JacobianSink* jacobian) {
  const Vec3 v = ctx.nodeVelocity(node);
  const double s = std::sqrt(v.squaredNorm() + velocity_scale * velocity_scale);
  force.segment<3>(3 * node) -= (yield_force / s) * v;  // F = -F_y v / sqrt(|v|^2 + v_s^2)
  if (!jacobian) return;
  // dF/dx = (1/dt) dF/dv = -(F_y/dt) (I/s - v v^T/s^3)
  const Mat3 dF_dv = -yield_force * (Mat3::Identity() / s - v * v.transpose() / (s * s * s));
  jacobian->addBlock(3 * node, 3 * node, dF_dv / ctx.dt);
}

GranularYield::GranularYield() : Effect(kName, granularYieldEffect().parameters) {
  yield_force_ = parameterIndex("yield_force");
  velocity_scale_ = parameterIndex("velocity_scale");
}

const EffectDescriptor& granularYieldEffect() {
  static const EffectDescriptor d = [] {
    EffectDescriptor e;
    e.name = GranularYield::kName;
    e.description = "granular yield stress: no head translation below a thrust threshold";
    e.parameters = {
        {"yield_force", 0.0, 0.0, 10.0, "N", "granular yield force F_y resisting head translation"},
        {"velocity_scale", 1e-6, 1e-9, 1e-2, "m/s",
         "regularisation speed v_s of the yield force's sign function"}};
    e.make = [](const EffectBuildContext&) { return std::make_unique<GranularYield>(); };
    DiscoveryHints h;
    h.title = "granular yield threshold";
    h.signature = "threshold: no translation below a motor speed, full speed above it";
    h.needs = kTranslation;
    h.variables = {{"yield_force", "yield_force", false, "N", 1e-7, 1.0, true, 1e-7}};
    h.starts = {{1e-5}, {1e-4}, {1e-3}};
    h.typical = {{"yield_force", 3e-4, 9e-4, false}};
    h.requires_effect = "rft";  // docs/model.md 2: the granular medium is RFT
    h.requires_what = "the granular medium's resistive force theory";
    e.discovery = h;
    return e;
  }();
  return d;
}

void GranularYield::attach(const RodNetwork& net) { node_ = net.parts.head_center_node; }

void GranularYield::addForce(const EffectContext& ctx, VecX& force, JacobianSink* jacobian) const {
  addRegularizedCoulombForce(ctx, node_, params_[yield_force_], params_[velocity_scale_], force,
                             jacobian);
}

}  // namespace flagella
