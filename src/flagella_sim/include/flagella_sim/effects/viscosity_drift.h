// Slow drift of the bath viscosity with temperature over an experimental session (model
// extension for identification): mu(t) = mu0 (1 + beta (t_s + t)/3600), t in s, beta in 1/h,
// applied through ViscosityLaw::viscosityFactor to every effect that reads the medium's viscosity.
// mu0 stays the medium parameter "medium.viscosity" (it may change between steps).
#pragma once

#include "flagella_sim/effects/effect.h"
#include "flagella_sim/effects/effect_descriptor.h"

namespace flagella {

/// The registry entry (effect_list.def).
const EffectDescriptor& viscosityDriftEffect();

class ViscosityDrift : public Effect, public ViscosityLaw {
 public:
  static constexpr const char* kName = "viscosity_drift";
  /// Smallest allowed mu/mu0; a drift that goes further throws instead of clamping.
  static constexpr double kMinFactor = 0.05;
  ViscosityDrift();
  /// 1 + beta (t_s + time)/3600; throws std::runtime_error naming effects.viscosity_drift.rate
  /// if it is <= kMinFactor.
  double viscosityFactor(double time) const override;

 private:
  int rate_ = 0, session_time_ = 0;
};

}  // namespace flagella
