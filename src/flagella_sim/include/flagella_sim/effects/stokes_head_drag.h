// Stokes-law drag and torque on the rigid head (docs/model.md 3.1):
// F = -C_t 6 pi mu a v_h on x_1, M = -C_r 8 pi mu a^3 Omega_h on theta^0, and optionally
// tilt_drag C_r 8 pi mu a^3 against the head's pitch and yaw, a couple on x_0 and x_2.
#pragma once

#include "flagella_sim/effects/effect.h"
#include "flagella_sim/effects/effect_descriptor.h"

namespace flagella {

/// The registry entry (effect_list.def).
const EffectDescriptor& stokesHeadDragEffect();

class StokesHeadDrag : public Effect, public ForceLaw {
 public:
  static constexpr const char* kName = "stokes_head";
  StokesHeadDrag(double C_t, double C_r, double head_radius, double tilt_drag = 0.0);
  void attach(const RodNetwork& net) override;
  void addForce(const EffectContext& ctx, VecX& force, JacobianSink* jacobian) const override;

 private:
  /// The pitch and yaw part: -k Omega_perp with k = tilt_drag C_r 8 pi mu a^3.
  void addTiltDrag(const EffectContext& ctx, double k, VecX& force, JacobianSink* jacobian) const;

  int c_t_ = 0, c_r_ = 0, radius_ = 0, tilt_ = 0;
  int node_ = 1, front_ = 0, back_ = 2;
  int theta_dof_ = 0;
};

}  // namespace flagella
