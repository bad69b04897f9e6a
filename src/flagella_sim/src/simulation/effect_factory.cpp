#include "flagella_sim/simulation/effect_factory.h"

#include "flagella_sim/effects/gravity.h"
#include "flagella_sim/effects/head_restraint.h"
#include "flagella_sim/effects/head_restraint.h"
#include "flagella_sim/effects/interface_lateral_force.h"
#include "flagella_sim/effects/rft_drag.h"
#include "flagella_sim/effects/stokes_head_drag.h"

namespace flagella {

namespace {

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
