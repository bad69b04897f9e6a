// Estimates the binary-input calibration (docs/model.md 7.3) from the core simulator: three fresh
// sessions (constant +omega, constant -omega, periodic switching) driven through SimSession and
// measured from its snapshots in the output frame (z up).
#pragma once

#include <string>

#include "flagella_control/calibration.h"
#include "flagella_sim/simulation/simulation_config.h"

namespace flagella::control {

struct CalibrationOptions {
  double omega = 0;              ///< |motor rate| [rad/s]; 0: the config's motor.omega_rpm
  double switch_period = 10.0;   ///< T of the switching run [s]; T/2 must be a whole number of dt
  double settle_time = 30.0;     ///< constant-sign runs: discarded start [s]
  double measure_time = 120.0;   ///< constant-sign runs: measured span after settling [s]
  int settle_periods = 2;        ///< switching run: discarded periods
  int measure_periods = 8;       ///< switching run: measured periods
  double sample_interval = 0.1;  ///< constant-sign runs: sampling of the head [s], whole dt

  /// Throws std::invalid_argument naming the field (non-finite, non-positive, too few samples).
  void validate() const;
};

/// |omega| the options select for a config: options.omega, or the config's motor rate.
double calibrationOmega(const flagella::SimulationConfig& config,
                        const CalibrationOptions& options);

/// Steady response at a constant signed motor rate (fresh session; settle, then measure).
/// Throws std::runtime_error if the session fails (solver failure) or a fit is invalid.
SignResponse measureSignResponse(const flagella::SimulationConfig& config, double signed_omega,
                                 const CalibrationOptions& options);

/// Net motion of periodic switching (+omega for T/2, then -omega for T/2).
struct SwitchingResponse {
  double advance_per_period = 0.0;        ///< |mean displacement per period| [m]
  double advance_angle = 0.0;             ///< its direction from the period-start heading [rad]
  double heading_drift_per_period = 0.0;  ///< mean heading change per period [rad]
  /// Spread of the per-period displacement (RMS distance from the mean vector) [m].
  double displacement_spread = 0.0;
};

/// Switching run (fresh session) with period options.switch_period at |omega|.
/// Throws std::runtime_error if the session fails.
SwitchingResponse measureSwitching(const flagella::SimulationConfig& config, double omega,
                                   const CalibrationOptions& options);

/// All three runs. source = config.source and the durations. The result is validated
/// (std::runtime_error if it is unusable, e.g. yaw rates of equal sign).
BinaryCalibration calibrate(const flagella::SimulationConfig& config,
                            const CalibrationOptions& options);

}  // namespace flagella::control
