#include "flagella_sim/effects/dc_motor.h"

namespace flagella {

DcMotor::DcMotor() : Effect(kName) {
  stall_torque_ =
      params_.declare("stall_torque", 1e6, 1e-6, 1e6, "N m",
                      "motor stall torque tau_stall (the command is the no-load speed)");
}

void DcMotor::addForce(const EffectContext& /*ctx*/, VecX& /*force*/,
                       JacobianSink* /*jacobian*/) const {}

double DcMotor::motorSpeed(double omega, const MotorLoad& load) const {
  const double stall = params_[stall_torque_];
  if (load.torque >= stall) return 0.0;        // stalled: tau_load >= tau_stall
  return omega * (1.0 - load.torque / stall);  // omega = omega_cmd (1 - tau_load/tau_stall)
}

}  // namespace flagella
