#include "flagella_sim/analysis/buckling_probe.h"

#include <chrono>
#include <stdexcept>

#include "flagella_sim/core/units.h"
#include "flagella_sim/simulation/simulation.h"

namespace flagella {

ThresholdProbe runBucklingProbe(const SimulationConfig& config, double rpm) {
  ThresholdProbe p;
  p.rate = rpm;
  SimulationConfig c = config;
  c.motor.mode = "constant";
  c.motor.omega = (config.motor.omega < 0.0 ? -1.0 : 1.0) * rpm * units::kRadPerSecPerRpm;
  const auto t0 = std::chrono::steady_clock::now();
  try {
    Simulation sim(c);
    sim.run(c.duration);
    const SummaryMetrics m = sim.summary();
    p.above = m.buckled;
    p.indicator = units::radToDeg(m.flagellum_tilt_max);
  } catch (const std::exception& e) {  // SolverFailure, or an effect out of its domain
    p.failed = true;
    p.error = e.what();
  }
  p.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return p;
}

}  // namespace flagella
