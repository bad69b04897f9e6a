#include "flagella_sim/effects/gravity.h"

namespace flagella {

Gravity::Gravity(double body_density) : Effect(kName) {
  body_density_ = params_.declare("body_density", body_density, 1e-3, 1e5, "kg/m^3",
                                  "density of the robot's material (sets buoyancy)");
}

void Gravity::addForce(const EffectContext& ctx, VecX& force, JacobianSink* /*jacobian*/) const {
  const double net_fraction = 1.0 - ctx.medium.density() / params_[body_density_];
  for (int i = 0; i < ctx.net.numNodes(); ++i)
    force.segment<3>(3 * i) += net_fraction * ctx.net.lumped_mass(3 * i) * ctx.medium.gravity;
}

}  // namespace flagella
