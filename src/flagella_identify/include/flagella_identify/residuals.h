// Residuals of a model against measured data, and the simulated series they are taken from.
#pragma once

#include <string>
#include <vector>

#include "flagella_identify/measured_data.h"

namespace flagella {
namespace identify {

/// Where one residual comes from.
struct ResidualPoint {
  std::string output;  ///< v, omega_h, omega_t, omega_yr, R_yr | x, y, z | axis_x.. | head_turns,
                       ///< tail_turns
  bool from_series = false;
  int source = 0;             ///< table or series index
  int row = 0;                ///< table row index, or sample index in the series
  double omega_T = 0.0;       ///< commanded motor speed there [rad/s]
  double session_time = 0.0;  ///< time in the session [s] (NaN if unknown)
  double run_time = 0.0;      ///< time in the run [s] (series), 0 for tables
  double data = 0.0, model = 0.0, sigma = 1.0;
  /// A table row whose model run buckled (SummaryMetrics::buckled): its speeds are those of a
  /// whirling flagellum, not a steady state (no measurement is suggested there).
  bool buckled = false;
  double z() const { return (model - data) / sigma; }
};

struct Evaluation {
  bool ok = true;
  std::string failure;  ///< why the simulation failed (Newton, config), if !ok
  std::vector<ResidualPoint> points;
};

/// Simulated series (every sample time) for plotting: time, head position, axis, turns.
struct SeriesTrace {
  std::vector<double> t;
  std::vector<Vec3> position, axis;
  std::vector<double> head_turns, tail_turns;
  Vec3 up = Vec3::UnitZ();  ///< the model's world vertical
};

}  // namespace identify
}  // namespace flagella
