#include "flagella_sim/effects/gravity.h"

namespace flagella {

Gravity::Gravity(double body_density) : Effect(kName, gravityEffect().parameters) {
  body_density_ = parameterIndex("body_density", body_density);
}

const EffectDescriptor& gravityEffect() {
  static const EffectDescriptor d = [] {
    EffectDescriptor e;
    e.name = Gravity::kName;
    e.description = "gravity minus buoyancy on every node's lumped mass";
    e.parameters = {{"body_density", 1000.0, 1e-3, 1e5, "kg/m^3",
                     "density of the robot's material (sets buoyancy)"}};
    e.default_rules = {{"body_density", "robot.density"}};
    e.make = [](const EffectBuildContext& c) {
      return std::make_unique<Gravity>(c.robot.body_density);
    };
    return e;
  }();
  return d;
}

void Gravity::addForce(const EffectContext& ctx, VecX& force, JacobianSink* /*jacobian*/) const {
  const double net_fraction = 1.0 - ctx.medium.density() / params_[body_density_];
  for (int i = 0; i < ctx.net.numNodes(); ++i)
    force.segment<3>(3 * i) += net_fraction * ctx.net.lumped_mass(3 * i) * ctx.medium.gravity;
}

}  // namespace flagella
