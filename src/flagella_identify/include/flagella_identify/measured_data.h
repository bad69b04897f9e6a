// Measured data as the identification tool sees it: steady-state tables (one row per
// experiment) and time series (one run), both in SI units, with the measurement noise the
// significance tests use. Readers and writers live in data_io.h (CSV + YAML metadata) and
// bag_reader.h (bags of the project's own topics).
#pragma once

#include <Eigen/Geometry>
#include <limits>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "flagella_sim/core/types.h"

namespace flagella {
namespace identify {

constexpr double kMissing = std::numeric_limits<double>::quiet_NaN();

/// The steady-state outputs a table may hold (docs/model.md 7.1), SI units.
/// "v" [m/s], "omega_h" [rad/s], "omega_t" [rad/s], "omega_yr" [rad/s], "R_yr" [m],
/// "buckling_threshold" [rad/s] (motor rate at which the flagellum buckles; the row's omega_T is
/// then unused).
const std::vector<std::string>& steadyOutputNames();

/// A config override "section.field" -> YAML value text (e.g. "robot.n_tails" -> "3").
using ConfigOverride = std::pair<std::string, std::string>;

struct SteadyStateRow {
  int line = 0;            ///< line of the row in its CSV file (1-based), for messages
  std::string id;          ///< optional experiment name
  double omega_T = 0.0;    ///< signed motor speed [rad/s] (0 in a threshold-only table)
  double time = kMissing;  ///< start of the experiment in the session [s] (optional)
  std::vector<ConfigOverride> overrides;   ///< per-row config fields (n_tails, tail length, ...)
  std::map<std::string, double> measured;  ///< output name -> value (NaN = not measured)
  /// output name -> this row's one standard deviation (SI), from a sigma_<column> cell; the
  /// table's noise applies where absent
  std::map<std::string, double> sigma;
  /// The uncertainty of the row's `output`: its own, else the table's (NaN if neither).
  double sigmaOf(const std::string& output, const std::map<std::string, double>& table_noise) const;
};

struct SteadyStateTable {
  std::string source;                     ///< metadata file path
  std::string csv;                        ///< the CSV file it names (for messages; may be empty)
  std::string description;                ///< free text from the metadata
  double settle_time = 0.0;               ///< time the robot ran before the measurement window [s]
  double window = 0.0;                    ///< length of the measurement window [s]
  std::map<std::string, double> noise;    ///< output name -> one standard deviation (SI); rows
                                          ///< may give their own (SteadyStateRow::sigma)
  std::vector<ConfigOverride> overrides;  ///< config fields common to all rows
  std::vector<SteadyStateRow> rows;
};

struct TimeSeries {
  std::string source;
  std::string description;
  double session_time = 0.0;  ///< start of the run in the session [s] (drift effects)
  std::vector<ConfigOverride> overrides;
  std::vector<double> t;       ///< [s], strictly increasing, t[0] is the start of the run
  std::vector<Vec3> position;  ///< head centre in the simulator's world frame [m]
  bool has_z = false;          ///< false: 2-D tracking (the vertical coordinate is not measured)
  std::vector<Eigen::Quaterniond> orientation;  ///< head frame (m1, m2, t); empty if absent
  std::vector<double> head_turns;               ///< cumulative counted head turns; empty if absent
  std::vector<double> tail_turns;               ///< cumulative counted tail turns; empty if absent
  std::vector<double> omega_cmd;   ///< motor command [rad/s], held from each sample to the next
  double position_noise = 0.0;     ///< [m] per coordinate
  double orientation_noise = 0.0;  ///< [rad] per axis component
  double turns_noise = 0.0;        ///< [turns]
};

}  // namespace identify
}  // namespace flagella
