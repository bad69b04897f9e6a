// Gravity minus buoyancy on every node's lumped mass: F_i = (1 - rho_m/rho_body) m_i g.
// The Jacobian is zero because the forces are constant vectors (docs/model.md 5).
#pragma once

#include "flagella_sim/effects/effect.h"
#include "flagella_sim/effects/effect_descriptor.h"

namespace flagella {

/// The registry entry (effect_list.def).
const EffectDescriptor& gravityEffect();

class Gravity : public Effect, public ForceLaw {
 public:
  static constexpr const char* kName = "gravity";
  explicit Gravity(double body_density);
  void addForce(const EffectContext& ctx, VecX& force, JacobianSink* jacobian) const override;

 private:
  int body_density_ = 0;
};

}  // namespace flagella
