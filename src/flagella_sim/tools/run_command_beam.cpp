// flagella_run beam: the Euler-Bernoulli beam model (docs/model.md 6) of a multi-tail design.
#include <cmath>
#include <cstdio>
#include <vector>

#include "flagella_sim/beam/euler_bernoulli_beam.h"
#include "flagella_sim/core/units.h"
#include "flagella_sim/effects/rft_drag.h"
#include "flagella_sim/simulation/simulation.h"
#include "run_command_shared.h"
#include "run_commands.h"

namespace flagella::cli {

int beamCommand(const BeamOptions& o) {
  const SimulationConfig c = loadSimulationConfig(o.config, o.overrides);
  const MultiTailGeometry* g = c.findRobotGeometry<MultiTailGeometry>();
  if (!g)
    throw ConfigError(o.config + ": robot.type " + c.robotType() +
                      ": the beam model (docs/model.md 6) is for the multi-tail robots");
  beam::BeamDesign d;
  d.n_tails = g->n_tails;
  d.tail_length = g->tail_length;
  d.tail_radius = g->tail_material.radius;
  d.youngs_modulus = g->tail_material.youngs_modulus;
  d.disc_radius = g->disc_radius;
  d.head_radius = c.head_radius;
  d.viscosity = c.medium.viscosity();
  d.log_form = RftLogForm::kTwoLengthOverRadius;
  // The beam model uses the same (validated) effect parameters as the rod model.
  const Simulation probe(c);
  d.C_t = probe.parameter("effects.stokes_head.C_t");
  d.C_r = probe.parameter("effects.stokes_head.C_r");
  d.head_radius = probe.parameter("effects.stokes_head.head_radius");
  if (const EffectSpec* rft = c.effect(RftDrag::kName))
    d.log_form = parseRftLogForm(rft->option("log_form"));
  const double omega = std::abs(c.motor.omega);
  std::vector<beam::BeamRegime> regimes;
  if (o.regime == "LB" || o.regime == "all") regimes.push_back(beam::BeamRegime::kLinear);
  if (o.regime == "NLB" || o.regime == "all") regimes.push_back(beam::BeamRegime::kNonlinear);
  if (o.regime == "NLB-no-head" || o.regime == "all")
    regimes.push_back(beam::BeamRegime::kNonlinearWithoutHead);
  std::printf("beam model (docs/model.md 6), %s, n = %d, omega_T = %.3f rpm\n", o.config.c_str(),
              d.n_tails, units::radPerSecToRpm(omega));
  std::printf("%-14s %12s %12s %14s %12s %14s\n", "model", "omega_h rpm", "omega_t rpm", "v mm/s",
              "w(L)/L", "F_p/tail N");
  for (beam::BeamRegime regime : regimes) {
    const beam::BeamSolution s = beam::solveBeamModel(d, omega, regime);
    std::printf("%-14s %12.5f %12.5f %14.6g %12.5f %14.6g%s\n", beam::toString(regime).c_str(),
                units::radPerSecToRpm(s.omega_h), units::radPerSecToRpm(s.omega_t),
                units::metresToMm(s.speed), s.relative_tip_deflection, s.propulsive_force,
                s.converged ? "" : "  (not converged)");
  }
  if (o.compare_rod) {
    Simulation sim(c);
    const RunResult r = simulate(c, sim, o.quiet);
    const SummaryMetrics& m = r.summary;
    const double propulsive =
        d.C_t * 6.0 * M_PI * d.viscosity * d.head_radius * m.speed / d.n_tails;
    std::printf("%-14s %12.5f %12.5f %14.6g %12s %14.6g\n", "rod (DER)",
                units::radPerSecToRpm(m.omega_h), units::radPerSecToRpm(m.omega_t),
                units::metresToMm(m.speed), "-", propulsive);
    if (r.failed) return 3;
  }
  return 0;
}

}  // namespace flagella::cli
