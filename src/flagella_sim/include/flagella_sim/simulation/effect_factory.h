// Turns an EffectSpec from a config into an Effect instance (the one place effects are named).
#pragma once

#include "flagella_sim/effects/effect.h"
#include "flagella_sim/simulation/simulation_config.h"

namespace flagella {

EffectPtr makeEffect(const EffectSpec& spec, const SimulationConfig& config);

}  // namespace flagella
