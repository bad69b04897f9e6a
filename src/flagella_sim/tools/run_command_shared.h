// What flagella_run's subcommands share: one simulation run to its end, timed (internal header).
#pragma once

#include <string>

#include "flagella_sim/simulation/simulation.h"

namespace flagella::cli {

struct RunResult {
  SummaryMetrics summary;
  double wall = 0.0;
  bool failed = false;
  std::string error;
};

/// Runs `sim` for `config.duration` with a progress line (none if `quiet`); a solver failure
/// ends the run early and is recorded in the result, not thrown.
RunResult simulate(const SimulationConfig& config, Simulation& sim, bool quiet);

}  // namespace flagella::cli
