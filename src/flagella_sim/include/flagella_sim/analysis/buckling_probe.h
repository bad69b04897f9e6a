// One buckling-threshold run (docs/model.md 8.4.4): the configured robot at a given motor rate for
// the configured duration, classified by the flagellum's largest tilt in the steady window.
#pragma once

#include "flagella_sim/analysis/threshold_search.h"
#include "flagella_sim/simulation/simulation_config.h"

namespace flagella {

/// Runs `config` with a constant motor at `rpm` in magnitude (the sign of config.motor.omega, +
/// if it is zero; the configured ramp is kept): `above` = buckled, `indicator` = largest tilt
/// [deg]. Solver failures are returned as failed runs, never thrown.
ThresholdProbe runBucklingProbe(const SimulationConfig& config, double rpm);

}  // namespace flagella
