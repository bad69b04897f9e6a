#include "flagella_sim/effects/viscosity_drift.h"

#include <sstream>
#include <stdexcept>

#include "flagella_sim/core/units.h"

namespace flagella {

ViscosityDrift::ViscosityDrift() : Effect(kName, viscosityDriftEffect().parameters) {
  rate_ = parameterIndex("rate");
  session_time_ = parameterIndex("session_time");
}

const EffectDescriptor& viscosityDriftEffect() {
  static const EffectDescriptor d = [] {
    EffectDescriptor e;
    e.name = ViscosityDrift::kName;
    e.description = "slow drift of the bath viscosity with temperature over a session";
    // |beta| <= 2/h: the range discovery fits; the run's own check (mu/mu0 > kMinFactor over the
    // session) rejects a drift that would make the viscosity vanish.
    e.parameters = {
        {"rate", 0.0, -2.0, 2.0, "1/h", "relative drift rate beta of the bath viscosity"},
        {"session_time", 0.0, 0.0, 1e6, "s",
         "time t_s in the experimental session at which the run starts"}};
    e.make = [](const EffectBuildContext&) { return std::make_unique<ViscosityDrift>(); };
    DiscoveryHints h;
    h.title = "slow viscosity drift with temperature";
    h.signature = "drift: the same experiment gives different speeds at different session times";
    h.needs = kSessionTime;
    h.variables = {{"rate", "rate", false, "1/h", -2.0, 2.0, false, 0.0}};
    h.starts = {{-0.1}, {0.1}};
    h.session_time_parameter = "session_time";
    h.typical = {{"rate", 0.04, 0.12, true}};
    e.discovery = h;
    return e;
  }();
  return d;
}

double ViscosityDrift::viscosityFactor(double time) const {
  const double beta = params_[rate_], t_s = params_[session_time_];
  const double factor =
      1.0 + beta * (t_s + time) / units::kSecondsPerHour;  // mu/mu0 = 1 + beta t/3600
  if (!(factor > kMinFactor)) {
    std::ostringstream msg;
    msg << "effects.viscosity_drift.rate = " << beta << " 1/h gives mu/mu0 = " << factor
        << " <= " << kMinFactor << " at t = " << time << " s (session time t_s + t = " << t_s + time
        << " s); reduce |rate| or effects.viscosity_drift.session_time";
    throw std::runtime_error(msg.str());
  }
  return factor;
}

}  // namespace flagella
