#include "flagella_sim/simulation/effect_factory.h"

#include <cmath>

#include "flagella_sim/effects/com_offset.h"
#include "flagella_sim/effects/dc_motor.h"
#include "flagella_sim/effects/granular_jamming.h"
#include "flagella_sim/effects/granular_yield.h"
#include "flagella_sim/effects/gravity.h"
#include "flagella_sim/effects/head_restraint.h"
#include "flagella_sim/effects/interface_lateral_force.h"
#include "flagella_sim/effects/rft_drag.h"
#include "flagella_sim/effects/stokes_head_drag.h"
#include "flagella_sim/effects/viscosity_drift.h"

namespace flagella {

namespace {

// com_offset's head mass: m_h = rho_m pi a^2 L_head (spec 5) unless the config gives it (then
// any in-range value serves until the configured one is set).
double comOffsetHeadMass(const EffectSpec& spec, const SimulationConfig& c) {
  for (const auto& parameter : spec.parameters)
    if (parameter.first == "head_mass") return ComOffset::kMinHeadMass;
  const double m = c.medium.density() * M_PI * c.head_radius * c.head_radius * c.head_length;
  if (!(m >= ComOffset::kMinHeadMass && m <= ComOffset::kMaxHeadMass))
    throw ConfigError(rangeMessage("effects.com_offset.head_mass (default rho_m pi a^2 L_head)", m,
                                   ComOffset::kMinHeadMass, ComOffset::kMaxHeadMass, "kg") +
                      "; give effects.com_offset.head_mass");
  return m;
}

EffectPtr construct(const EffectSpec& spec, const SimulationConfig& c) {
  if (spec.name == RftDrag::kName)
    return std::make_unique<RftDrag>(parseRftLogForm(spec.log_form), spec.use_interface_profile);
  if (spec.name == StokesHeadDrag::kName)
    return std::make_unique<StokesHeadDrag>(1.0, 1.0, c.head_radius);
  if (spec.name == InterfaceLateralForce::kName) {
    double c_yr = 0.0;
    if (spec.lateral_mode == "integrated") {
      // spec 3.3: C_yr from the viscosity profile integral I(h/R, k)
      const InterfaceViscosityProfile& p = c.medium.profile;
      c_yr = integratedLateralCoefficient(p.onset_height / p.length_scale, p.sharpness);
    }
    return std::make_unique<InterfaceLateralForce>(c_yr, c.head_radius, c.head_length);
  }
  if (spec.name == Gravity::kName)
    return std::make_unique<Gravity>(c.geometry.tail_material.density);
  if (spec.name == HeadRestraint::kName) return std::make_unique<HeadRestraint>(0.0, 0.0);
  if (spec.name == GranularYield::kName) return std::make_unique<GranularYield>();
  if (spec.name == GranularJamming::kName) return std::make_unique<GranularJamming>();
  if (spec.name == ComOffset::kName) return std::make_unique<ComOffset>(comOffsetHeadMass(spec, c));
  if (spec.name == ViscosityDrift::kName) return std::make_unique<ViscosityDrift>();
  if (spec.name == DcMotor::kName) return std::make_unique<DcMotor>();
  throw ConfigError("unknown effect '" + spec.name + "'");
}

}  // namespace

EffectPtr makeEffect(const EffectSpec& spec, const SimulationConfig& config) {
  EffectPtr effect = construct(spec, config);
  for (const auto& [name, value] : spec.parameters) {
    if (spec.name == InterfaceLateralForce::kName && spec.lateral_mode == "integrated" &&
        name == "C_yr")
      throw ConfigError(
          "effects.interface_lateral_force.C_yr is computed in mode 'integrated'; remove it or use "
          "mode 'fitted'");
    effect->parameters().set(name, value, "effects." + spec.name);
  }
  return effect;
}

}  // namespace flagella
