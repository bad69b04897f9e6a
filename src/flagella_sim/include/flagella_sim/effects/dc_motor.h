// DC-motor torque-speed curve (model extension for identification): the commanded omega_T is
// the no-load speed, and the motor turns the natural twist (docs/model.md 1.9) at
// omega = omega_cmd (1 - tau_load/tau_stall), or 0 once tau_load >= tau_stall (stall).
// tau_load is the motor spring's moment on the head edge measured along the command's sign,
// taken at the start of the step (MotorLoad: a one-step lag).
#pragma once

#include "flagella_sim/effects/effect.h"
#include "flagella_sim/effects/effect_descriptor.h"

namespace flagella {

/// The registry entry (effect_list.def).
const EffectDescriptor& dcMotorEffect();

class DcMotor : public Effect, public MotorSpeedLaw {
 public:
  static constexpr const char* kName = "dc_motor";
  DcMotor();
  double motorSpeed(double omega, const MotorLoad& load) const override;

 private:
  int stall_torque_ = 0;
};

}  // namespace flagella
