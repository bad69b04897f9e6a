// Buckling-threshold runs of the helical robot (docs/model.md 8.4.4): a yes/no run classified by
// the flagellum's largest tilt (the secondary report), and a growth-rate run that measures how
// fast the flagellum's slow tilt grows or decays (the threshold's definition).
#pragma once

#include "flagella_sim/analysis/growth_rate.h"
#include "flagella_sim/analysis/threshold_search.h"
#include "flagella_sim/simulation/simulation_config.h"

namespace flagella {

/// Runs `config` with a constant motor at `rpm` in magnitude (the sign of config.motor.omega, +
/// if it is zero; the configured ramp is kept): `above` = buckled, `indicator` = largest tilt
/// [deg]. Solver failures are returned as failed runs, never thrown.
ThresholdProbe runBucklingProbe(const SimulationConfig& config, double rpm);

/// How a growth-rate run is made and read (docs/model.md 8.4.4).
/// Times are counted in turns of the flagellum (its twist angle theta^1 from the start): near
/// the threshold its elastic relaxation and its turn take comparable times, whatever its
/// stiffness, and untethered it turns several times slower than the motor.
struct GrowthProbeOptions {
  double observe_turns = 8.0;    ///< run length T [flagellum turns]
  double settle_turns = 3.0;     ///< the fit window starts here [flagellum turns]
  double small_tilt_deg = 10.0;  ///< the window ends where the slow tilt first exceeds this [deg]
  /// ... or where it has fallen to this fraction of its value at the window's start
  /// (readGrowth).
  double decay_limit = 0.25;
  /// A slow tilt whose one-turn movement is below this fraction of its peak before the window
  /// has decayed (readGrowth).
  double decayed_before = 0.05;
  int samples_per_period = 24;  ///< tilt samples per motor turn
};
void validate(const GrowthProbeOptions& options);

/// Runs `config` at a constant `rpm` (as runBucklingProbe) from the straight helix until the
/// flagellum has turned options.observe_turns times, sampling its tilt vector
/// (flagellumTiltVector), and reads the growth rate of the slow part (slowTiltAmplitude over the
/// mean turn after settling, readGrowth from options.settle_turns on). The spin-up from rest is
/// the perturbation. Solver failures are returned as failed runs.
GrowthProbe runGrowthProbe(const SimulationConfig& config, double rpm,
                           const GrowthProbeOptions& options);

}  // namespace flagella
