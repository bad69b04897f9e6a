// Gravity couple from an axial offset l between the head's centre of mass and centre of
// buoyancy (docs/model.md 5): +M_a g on the COM-side head node and -M_a g on the other, nodes x_0
// (front) and x_2 (joint), M_a = m_h |l| / d with d = |x_2 - x_0| of the undeformed network
// [CORR-28]. Net force zero, couple l ahat x (m_h g). Zero Jacobian (constant vectors).
#pragma once

#include "flagella_sim/effects/effect.h"
#include "flagella_sim/effects/effect_descriptor.h"

namespace flagella {

/// The registry entry (effect_list.def).
const EffectDescriptor& comOffsetEffect();

class ComOffset : public Effect, public ForceLaw {
 public:
  static constexpr const char* kName = "com_offset";
  static constexpr double kMinHeadMass = 1e-6;  ///< [kg]
  static constexpr double kMaxHeadMass = 10.0;  ///< [kg]
  /// `head_mass` is m_h [kg]; the config default is rho_m pi a^2 L_head (docs/model.md 5).
  explicit ComOffset(double head_mass);
  void attach(const RodNetwork& net) override;
  void addForce(const EffectContext& ctx, VecX& force, JacobianSink* jacobian) const override;

 private:
  int offset_ = 0, head_mass_ = 0;
  int front_ = 0, joint_ = 2;
  double separation_ = 1.0;  ///< d = |x_2 - x_0| at rest [m]
};

}  // namespace flagella
