// Rotation-induced lateral force on a head spinning at an air-liquid interface (docs/model.md 3.3):
// F = -C_yr mu0 R L_head (yhat x (Omega_h ahat)) on x_1. C_yr is either the fitted constant or
// the integral of the sigmoid viscosity profile over the head surface.
#pragma once

#include "flagella_sim/effects/effect.h"
#include "flagella_sim/effects/effect_descriptor.h"

namespace flagella {

/// The registry entry (effect_list.def).
const EffectDescriptor& interfaceLateralForceEffect();

/// -I(h/R, k) with I = integral_0^{2pi} sin(phi) mu(R sin phi)/mu0 dphi (docs/model.md 3.3).
double integratedLateralCoefficient(double onset_over_radius, double sharpness);

class InterfaceLateralForce : public Effect, public ForceLaw {
 public:
  static constexpr const char* kName = "interface_lateral_force";
  InterfaceLateralForce(double C_yr, double head_radius, double head_length);
  void attach(const RodNetwork& net) override;
  void addForce(const EffectContext& ctx, VecX& force, JacobianSink* jacobian) const override;

 private:
  int c_yr_ = 0, radius_ = 0, length_ = 0;
  int front_ = 0, center_ = 1, theta_dof_ = 0;
};

}  // namespace flagella
