// Measured-style data sets from a truth model: the simulator with chosen parameters and
// hidden effects, sampled the way experiments are (steady-state tables from counted turns and
// tracked displacement; time series from video tracking, an IMU and turn counting) with
// Gaussian measurement noise of the documented size. Tests hide an effect in such data.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "flagella_identify/data_io.h"
#include "flagella_identify/evaluation.h"
#include "flagella_identify/model.h"

namespace flagella {
namespace identify {

struct TablePlan {
  std::vector<double> omega_rpm;  ///< signed motor speeds, each run for every tail count
  std::vector<int> n_tails;       ///< tail counts (robot.n_tails overrides; none: the baseline's)
  double settle_time = 10.0;      ///< [s]
  double window = 30.0;           ///< [s]
  double session_hours = 4.0;     ///< experiments in random order over this many hours
  double v_noise = 3e-6;          ///< [m/s]
  double omega_noise = 0.05;      ///< [rad/s], from counting turns over the window
  bool measure_rotation = true;   ///< write omega_h / omega_t
  /// [rad]: > 0 writes the flagellum's mean tilt with this noise (a helical robot only)
  double tilt_noise = 0.0;
};

struct SeriesPlan {
  /// Command steps: (start time [s], omega [rpm]); the first must start at 0.
  std::vector<std::pair<double, double>> command_rpm = {{0.0, 150.0}};
  double duration = 120.0;          ///< [s]
  double sample_interval = 0.5;     ///< [s]
  double session_time = 0.0;        ///< [s]
  double position_noise = 2e-4;     ///< [m] video tracking, per coordinate
  double orientation_noise = 0.01;  ///< [rad] IMU, per axis component
  double turns_noise = 0.1;         ///< [turns] counting
  bool has_z = true;
  bool orientation = true;
  bool turns = true;
  /// An effect outside the candidate list: the motor's real speed ripples by this fraction
  /// with the period below, while the data record the nominal command.
  double ripple_fraction = 0.0;
  double ripple_period = 12.0;  ///< [s]
};

/// A steady-state table from `truth` (values applied), noise drawn with `seed`.
SteadyStateTable generateTable(const Model& truth, const TablePlan& plan, std::uint64_t seed,
                               const EvaluatorOptions& options = {});
/// A time series from `truth`, noise drawn with `seed`.
TimeSeries generateSeries(const Model& truth, const SeriesPlan& plan, std::uint64_t seed,
                          const EvaluatorOptions& options = {});

}  // namespace identify
}  // namespace flagella
