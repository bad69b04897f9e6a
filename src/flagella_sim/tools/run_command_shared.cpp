// The helpers flagella_run's subcommands share (run_command_shared.h).
#include "run_command_shared.h"

#include <chrono>
#include <functional>

#include "flagella_sim/runtime/progress_printer.h"

namespace flagella::cli {

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

}  // namespace

RunResult simulate(const SimulationConfig& config, Simulation& sim, bool quiet) {
  RunResult r;
  ProgressPrinter progress(config.duration, quiet);
  const Clock::time_point t0 = Clock::now();
  try {
    sim.run(config.duration, std::ref(progress));
  } catch (const SolverFailure& e) {
    r.failed = true;
    r.error = e.what();
  }
  r.wall = secondsSince(t0);
  r.summary = sim.summary();
  return r;
}

}  // namespace flagella::cli
