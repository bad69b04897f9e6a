// Granular yield stress on the head (model extension for identification): a regularised Coulomb
// force F = -F_y v/sqrt(|v|^2 + v_s^2) on the head centre x_1, so the head does not translate
// while the thrust is below F_y. v_s only smooths the sign function for Newton.
#pragma once

#include "flagella_sim/effects/effect.h"
#include "flagella_sim/effects/effect_descriptor.h"

namespace flagella {

/// The registry entry (effect_list.def).
const EffectDescriptor& granularYieldEffect();

/// Adds F = -F_y v/s, s = sqrt(|v|^2 + v_s^2), v = ctx.nodeVelocity(node), to `node` and, if
/// `jacobian` is given, the exact dF/dx = -(F_y/dt)(I/s - v v^T/s^3) (always the same entries).
/// Shared by granular_yield and granular_jamming.
void addRegularizedCoulombForce(const EffectContext& ctx, int node, double yield_force,
                                double velocity_scale, VecX& force, JacobianSink* jacobian);

class GranularYield : public Effect, public ForceLaw {
 public:
  static constexpr const char* kName = "granular_yield";
  GranularYield();
  void attach(const RodNetwork& net) override;
  void addForce(const EffectContext& ctx, VecX& force, JacobianSink* jacobian) const override;

 private:
  int yield_force_ = 0, velocity_scale_ = 0;
  int node_ = 1;
};

}  // namespace flagella
