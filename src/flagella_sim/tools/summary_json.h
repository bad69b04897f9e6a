// summary.json of a flagella_run run: the steady-window metrics plus the run's key inputs.
#pragma once

#include <string>

#include "flagella_sim/outputs/trajectory.h"
#include "flagella_sim/simulation/simulation_config.h"

namespace flagella {

/// Summary metrics (SI and rpm) plus the run's key inputs.
std::string summaryJson(const SimulationConfig& config, const SummaryMetrics& m,
                        double wall_seconds);

}  // namespace flagella
