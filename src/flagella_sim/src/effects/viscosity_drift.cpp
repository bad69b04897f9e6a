#include "flagella_sim/effects/viscosity_drift.h"

#include <sstream>
#include <stdexcept>

namespace flagella {

namespace {
constexpr double kSecondsPerHour = 3600.0;
}

ViscosityDrift::ViscosityDrift() : Effect(kName) {
  rate_ = params_.declare("rate", 0.0, -1.0, 1.0, "1/h",
                          "relative drift rate beta of the bath viscosity");
  session_time_ = params_.declare("session_time", 0.0, 0.0, 1e6, "s",
                                  "time t_s in the experimental session at which the run starts");
}

void ViscosityDrift::addForce(const EffectContext& /*ctx*/, VecX& /*force*/,
                              JacobianSink* /*jacobian*/) const {}

double ViscosityDrift::viscosityFactor(double time) const {
  const double beta = params_[rate_], t_s = params_[session_time_];
  const double factor = 1.0 + beta * (t_s + time) / kSecondsPerHour;  // mu/mu0 = 1 + beta t/3600
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
