// Soft restraint of the head's height and pitch (docs/model.md 3.3 [ASSUMED]): the interface robot
// floats, and buoyancy and the vertical restoring force are not modelled, so a slow vertical drift
// or tilt can be held by E = 1/2 k_h ((x_1 - x_1(0)).up)^2 + 1/2 k_p (t^0 . up)^2.
#pragma once

#include "flagella_sim/effects/effect.h"
#include "flagella_sim/effects/effect_descriptor.h"

namespace flagella {

/// The registry entry (effect_list.def).
const EffectDescriptor& headRestraintEffect();

class HeadRestraint : public Effect, public ForceLaw {
 public:
  static constexpr const char* kName = "head_restraint";
  HeadRestraint(double height_stiffness, double pitch_stiffness);
  void attach(const RodNetwork& net) override;
  void addForce(const EffectContext& ctx, VecX& force, JacobianSink* jacobian) const override;

 private:
  int height_k_ = 0, pitch_k_ = 0;
  int front_ = 0, center_ = 1;
  Vec3 rest_center_ = Vec3::Zero();
};

}  // namespace flagella
