// The smallest cross-track error a schedule of the single binary input can achieve on a path,
// with perfect state knowledge, on the calibrated model (docs/model.md 7.5): a dynamic program
// over switching periods. Every period has the calibration's length T and holds +omega for a
// share k / duty_steps of it, then -omega; its motion, sampled inside the period, comes from
// DeadTimeModel. After each period the states are merged on a grid (progress along the path,
// signed cross-track error, heading against the path), the best of each cell kept. The result is
// the best schedule found: an estimate of the bound from above, which the grid's refinement
// settles (flagella_tracking_bound --refine prints both).
#pragma once

#include <vector>

#include "flagella_control/calibration.h"
#include "flagella_control/path.h"

namespace flagella::control {

struct TrackingBoundOptions {
  int duty_steps = 20;              ///< shares of +omega per period: 0, 1/n, ..., 1
  double sample_interval = 0.5;     ///< error sampled this often, as flagella_follow_path does [s]
  double progress_cell = 0.004;     ///< grid of the merge: progress along the path [m]
  double cross_track_cell = 0.001;  ///< signed cross-track error [m]
  double heading_cell = 0.02;       ///< heading against the path tangent [rad]
  int states_per_progress = 24;     ///< kept per progress cell (the best by the objective)
  double first_cap = 0.004;         ///< first error cap of the max search [m]
  double largest_cap = 1.0;         ///< no schedule within this error: no bound [m]
  double cap_tolerance = 2e-4;      ///< the max search ends with the cap this close [m]
  /// The RMS search: the error never beyond this factor of the max bound, and ...
  double rms_error_cap_factor = 1.5;
  double finish_tolerance = 0.02;  ///< done within this of the end, as the controllers [m]
  /// ... completion within this factor of the max-bound schedule's duration (lingering could
  /// otherwise dilute the RMS without end).
  double rms_time_factor = 1.1;
  double max_duration = 4000.0;  ///< give up after this long [s]
  /// The plan (TrackingBound::plan): the smallest RMS whose max error stays within this factor
  /// of the max bound (a controller's reference good in both).
  double plan_error_cap_factor = 1.05;
  /// Throws std::invalid_argument naming the field and its allowed range.
  void validate() const;
};

/// One schedule found by the search and its error on the calibrated model.
struct BoundSchedule {
  bool complete = false;               ///< reached the end of the path within max_duration
  double max_error = 0.0;              ///< [m]
  double rms_error = 0.0;              ///< [m]
  double duration = 0.0;               ///< [s]
  std::vector<double> plus_durations;  ///< +omega time of each period [s]
  std::vector<Vec2> samples;           ///< head position at each sample (start included) [m]
};

struct TrackingBound {
  BoundSchedule best_max;  ///< the schedule of the smallest max error
  BoundSchedule best_rms;  ///< the schedule of the smallest RMS error
  BoundSchedule plan;      ///< smallest RMS within plan_error_cap_factor of the max bound
  long states_expanded = 0;
  double dead_time = 0.0;           ///< of the model (DeadTimeModel) [s]
  double direction_mismatch = 0.0;  ///< measured minus modelled advance direction [rad]
};

/// Bound for `laps` laps of `path` (world frame; laps only for a closed path), the robot starting
/// at the path's start with its direction of advance along the first element. Throws
/// std::invalid_argument for an empty path or bad options.
TrackingBound computeTrackingBound(const Path& path, int laps, const BinaryCalibration& calibration,
                                   const TrackingBoundOptions& options = {});

}  // namespace flagella::control
