// What the mass-transformer robot offers a controller, measured in the simulator as tables
// (docs/model.md 7.4; flagella_steer_calibrate --turn-table / --slider-table): the turn of one
// buckle cycle against the pulse's rate and duration, for both schedules, with its phase law;
// and the slider's response against its offset from the park position: the initial pitch rate,
// the time to flip from level cruise to near vertical, and the time to come back level with the
// opposite offset; and what the slider held there does at the end of the hold: the elevation the
// head axis holds (or passes) and the rate at which its azimuth precesses.
#pragma once

#include <deque>
#include <functional>
#include <string>
#include <vector>

#include "flagella_control/head_attitude.h"
#include "flagella_control/steering_calibration.h"
#include "flagella_control/steering_calibration_runner.h"
#include "flagella_sim/simulation/simulation_config.h"

namespace flagella::control {

struct SteeringTableOptions {
  std::vector<double> pulse_factors;    ///< pulse rate / threshold, each > 1
  std::vector<double> pulse_durations;  ///< [s], each > 0
  std::vector<double> slider_offsets;   ///< from the park position [m], each != 0 (sign kept)
  double flip_elevation = 80.0 * M_PI / 180.0;  ///< |elevation of the head axis| counted as a flip
  double flip_timeout = 120.0;                  ///< [s] per flip or return
  double hold_window = 20.0;  ///< [s] the end of the hold over which the held attitude is fitted
  /// Throws std::invalid_argument naming the field and its range.
  void validate() const;
};

/// One buckle cycle's turn at one pulse rate and duration, both schedules (fitted phase laws).
struct BuckleTurnRow {
  double pulse_factor = 0.0, pulse_duration = 0.0;
  BuckleSchedule relax, three_level;
};

/// The slider held `offset` from the park position, from level cruise, then the opposite offset.
struct SliderResponseRow {
  double offset = 0.0;        ///< [m]
  double pitch_rate = 0.0;    ///< initial rate of the head axis's elevation (least squares) [rad/s]
  double flip_time = -1.0;    ///< to |elevation| >= flip_elevation [s]; -1: not within the timeout
  double return_time = -1.0;  ///< then, slider at -offset, back through level [s]; -1: not
  /// Change of the head axis's azimuth (unwrapped, positive to the left) over the hold (after the
  /// pitch-rate window) and over the return [rad].
  double hold_turn = 0.0, return_turn = 0.0;
  /// Over the last hold_window of the hold (which ends at the flip or at flip_timeout): the
  /// head axis's mean elevation, its elevation rate (near 0: held) and its azimuth rate
  /// (positive to the left, seen from above) [rad, rad/s].
  double end_elevation = 0.0, end_elevation_rate = 0.0, azimuth_rate = 0.0;
};

/// The head axis's attitude over a trailing window of samples: mean elevation and the
/// least-squares rates of elevation and of the azimuth, unwrapped across +-pi.
class HeldAttitudeWindow {
 public:
  explicit HeldAttitudeWindow(double window) : window_(window) {}
  /// Adds the direction of travel at time t (increasing); drops samples older than the window.
  void add(double t, const Vec3& forward);
  /// Mean elevation, elevation rate and azimuth rate over the samples kept; zeros for fewer
  /// than two samples.
  void fit(double& elevation, double& elevation_rate, double& azimuth_rate) const;
  /// Unwrapped azimuth of the last sample less that of the first ever added (0 if none).
  double azimuthChange() const { return samples_.empty() ? 0.0 : samples_.back().azimuth - first_; }

 private:
  struct Sample {
    double t, elevation, azimuth;
  };
  double window_;
  double first_ = 0.0;  ///< unwrapped azimuth of the first sample
  std::deque<Sample> samples_;
};

/// Both schedules at every (factor, duration) pair, with `calibration`'s threshold and cruise
/// and `options`' settle, window, pulses and lead/relax durations. `progress` gets one line
/// per row.
std::vector<BuckleTurnRow> measureBuckleTurnTable(
    const flagella::SimulationConfig& config, const SteeringCalibration& calibration,
    const SteeringTableOptions& table, const SteeringCalibrationOptions& options,
    const std::function<void(const std::string&)>& progress = {});

/// One run per offset from `calibration`'s park position at its cruise: settle, command the
/// offset, fit the pitch rate over options.pitch_window, time the flip (fitting the held attitude
/// over the hold's last table.hold_window), then, flipped or not, command the opposite offset
/// and time the return through level.
std::vector<SliderResponseRow> measureSliderTable(
    const flagella::SimulationConfig& config, const SteeringCalibration& calibration,
    const SteeringTableOptions& table, const SteeringCalibrationOptions& options,
    const std::function<void(const std::string&)>& progress = {});

/// CSV with a header line (angles in degrees, lengths in millimetres).
void writeBuckleTurnTable(const std::vector<BuckleTurnRow>& rows, const std::string& path);
void writeSliderTable(const std::vector<SliderResponseRow>& rows, const std::string& path);

}  // namespace flagella::control
