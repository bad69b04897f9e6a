// Estimates the steering calibration (docs/model.md 7.4) from the core simulator with the
// helical-robot tools: the buckling threshold (analysis/threshold_search), the cruise speed, the
// deflection of each buckle schedule and its phase law (a run of pulses started at different
// flagellum phases), the pitch rate per slider metre (a slider step with the head horizontal) and
// the crab angle per slider metre (two runs with the slider parked a few micrometres to either
// side of the park position).
#pragma once

#include <functional>
#include <string>

#include "flagella_control/steering_calibration.h"
#include "flagella_sim/analysis/threshold_search.h"
#include "flagella_sim/simulation/simulation_config.h"

namespace flagella::control {

struct SteeringCalibrationOptions {
  double threshold_rpm = 0.0;   ///< omega_b if known [rpm]; 0: search it
  double threshold_run = 20.0;  ///< duration of each threshold run [s]
  flagella::ThresholdSearchOptions search{8.0, 32.0, 0.1, 200.0, 1.0, 20};
  double cruise_fraction = 0.55;  ///< omega_3 = fraction x omega_b (0.7: slow buckling)
  double pulse_factor = 2.0;      ///< omega_2 = factor x omega_b
  double pulse_duration = 2.0;    ///< [s]
  double relax_duration = 12.0;   ///< relax schedule: omega_1 = 0 after the pulse [s]
  double lead_duration = 2.0;     ///< three_level: omega_1 = 0 before the pulse [s]
  int pulses = 8;                 ///< per schedule
  double settle_time = 15.0;      ///< before any measurement [s]
  double window = 10.7;           ///< mean direction of travel over this (about a head turn) [s]
  double after_cycle = 5.0;       ///< from a cycle's end to its after-window [s]
  double cruise_measure = 32.0;   ///< cruise speed: net displacement over this [s]
  double slider_step = 2e-3;      ///< pitch-rate run: slider step from the park position [m]
  double pitch_window = 4.0;      ///< pitch-rate run: fitted span after the step [s]
  double crab_step = 1e-5;        ///< crab runs: slider offsets +-this from the park position [m]
  double crab_settle = 30.0;      ///< crab runs: before the measurement [s]
  double crab_measure = 60.0;     ///< crab runs: course and axis over this [s]
  /// Cycles with the slider off park: pulses per side (0: not measured) and the offset from park
  /// held through each cycle [m] (up_per_slider, left_per_slider of each schedule).
  int slider_pulses = 4;
  double cycle_slider_step = 2e-5;
  /// Throws std::invalid_argument naming the field and its range.
  void validate() const;
};

/// What one calibration pulse showed (for reports and tests).
struct PulseObservation {
  double roll = 0.0, shaft = 0.0;  ///< at the cycle start [rad]
  double up = 0.0, left = 0.0;     ///< measured turn of the mean direction of travel [rad]
};

/// Fits the cycle model (steering_calibration.h) to observations by linear least squares on
/// the turn components (up, left) = bias + R(chi) (deflection, 0), for each sign pair; keeps the
/// pair with the smallest RMS residual (phase_spread). Fills bias_up, bias_left, deflection,
/// roll_sign, shaft_sign, phase_offset and phase_spread. Throws std::invalid_argument for fewer
/// than 3 observations.
void fitPhaseLaw(const std::vector<PulseObservation>& pulses, BuckleSchedule& schedule);

/// The whole calibration (several runs; minutes). The config needs a `slider:` section.
/// `progress` (optional) gets one line per finished part. Throws std::runtime_error on a solver
/// failure or an unusable result.
SteeringCalibration calibrateSteering(const flagella::SimulationConfig& config,
                                      const SteeringCalibrationOptions& options,
                                      const std::function<void(const std::string&)>& progress = {});

/// Crab angle (course over ground minus the head axis's azimuth, positive left) of a level
/// cruise with the slider held at `slider` [m] from `settle` to `settle + measure` [s] [rad].
double measureCrab(const flagella::SimulationConfig& config, double cruise_omega, double slider,
                   double settle, double measure);

/// Pulses of one schedule in one run (settle, then `pulses` cycles), for calibration; the slider
/// is held `cycle_offset` [m] off its start position through each cycle (at it otherwise).
std::vector<PulseObservation> observePulses(const flagella::SimulationConfig& config,
                                            const BuckleSchedule& schedule, double cruise_omega,
                                            const SteeringCalibrationOptions& options, int pulses,
                                            double cycle_offset = 0.0);

/// The turn per metre of slider offset held through a cycle, (up, left) [rad/m]: the mean
/// residual of the phase law over cycles at +step less that at -step, over 2 step.
void fitSliderTurn(const std::vector<PulseObservation>& plus,
                   const std::vector<PulseObservation>& minus, double step,
                   BuckleSchedule& schedule);

}  // namespace flagella::control
