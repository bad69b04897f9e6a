#include "flagella_sim/effects/dc_motor.h"

namespace flagella {

DcMotor::DcMotor() : Effect(kName, dcMotorEffect().parameters) {
  stall_torque_ = parameterIndex("stall_torque");
}

const EffectDescriptor& dcMotorEffect() {
  static const EffectDescriptor d = [] {
    EffectDescriptor e;
    e.name = DcMotor::kName;
    e.description = "DC-motor torque-speed curve: the command is the no-load speed";
    e.parameters = {{"stall_torque", 1e6, 1e-6, 1e6, "N m",
                     "motor stall torque tau_stall (the command is the no-load speed)"}};
    e.make = [](const EffectBuildContext&) { return std::make_unique<DcMotor>(); };
    DiscoveryHints h;
    h.title = "DC-motor torque-speed curve";
    h.signature =
        "saturation: head plus tail spin falls short of the commanded motor speed, "
        "more so under load";
    h.needs = kRotation;
    // Fitted as 1/tau_stall: the no-effect limit (tau_stall -> infinity) is then 0-ward.
    h.variables = {
        {"inverse_stall_torque", "stall_torque", true, "1/(N m)", 1e-2, 1e6, true, 1e-2}};
    h.starts = {{30.0}, {300.0}, {3000.0}};
    // 10-30 % speed loss at 250 rpm (load about 1.3e-3 N m)
    h.typical = {{"inverse_stall_torque", 80.0, 230.0, false}};
    e.discovery = h;
    return e;
  }();
  return d;
}

double DcMotor::motorSpeed(double omega, const MotorLoad& load) const {
  const double stall = params_[stall_torque_];
  if (load.torque >= stall) return 0.0;        // stalled: tau_load >= tau_stall
  return omega * (1.0 - load.torque / stall);  // omega = omega_cmd (1 - tau_load/tau_stall)
}

}  // namespace flagella
