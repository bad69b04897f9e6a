// The two path-following controller cores (ControllerCore contract: fixed step, no heap
// allocation in step(), binary motor output):
//  - ScheduleController: open loop, replays a planned switching schedule (docs/model.md 7.3).
//  - PathFollowingController: closed loop on an estimate of the head pose (IMU yaw at a high
//    rate, a noisy camera position fix at a low rate), line-of-sight guidance to the path and
//    duty-cycle switching; see the README's "Path following" section.
// Both anchor a path given in the robot's start frame at the first IMU sample (and the first
// camera fix, when one arrives by then) and report progress and errors through status().
#pragma once

#include "flagella_control/calibration.h"
#include "flagella_control/controller_core.h"
#include "flagella_control/heading.h"
#include "flagella_control/path.h"
#include "flagella_control/path_spec.h"
#include "flagella_control/switch_planner.h"

namespace flagella::control {

/// What a path-following controller knows about its progress (for ControllerStatus).
struct PathStatus {
  bool anchored = false;       ///< the path has been placed in the world
  int element = 0;             ///< current path element
  double progress = 0.0;       ///< fraction of the whole run (all laps), 0..1
  double cross_track = 0.0;    ///< estimated, left of the path > 0 [m]
  double heading_error = 0.0;  ///< desired minus estimated course [rad]
  bool imu_stale = false, fix_stale = false;
  bool mode_finished = false;  ///< the run is over (the motor stays stopped until reset)
  const char* message = "waiting for the first IMU sample";  ///< static text, never allocated
};

/// Places a path given in the robot's start frame at a start pose (world), or keeps a world path.
Path anchorPath(const PathSpec& spec, const BinaryCalibration& calibration, const Vec2& start,
                double start_heading);

class PathControllerBase : public ControllerCore {
 public:
  PathControllerBase(PathSpec spec, BinaryCalibration calibration);
  const PathStatus& status() const { return status_; }
  /// The path in world coordinates (valid once status().anchored).
  const Path& worldPath() const { return world_path_; }
  const BinaryCalibration& calibration() const { return calibration_; }

 protected:
  /// Anchors on the first valid IMU sample; returns false while waiting.
  bool anchorIfNeeded(const ControllerInputs& in);
  ControllerOutputs idle() const;
  ControllerOutputs finished();
  virtual void onAnchored(const ControllerInputs&, double /*heading*/) {}
  void resetBase();
  /// Arclength of the whole run: all laps of a closed path [m].
  double totalLength() const;

  PathSpec spec_;
  BinaryCalibration calibration_;
  Path world_path_;
  PathStatus status_;
  double start_time_ = 0.0;
  double first_imu_time_ = -1.0;
  bool have_fix_ = false;
  Vec2 first_fix_ = Vec2::Zero();
};

/// Open loop: the schedule planned for the anchored path, replayed against time.
class ScheduleController : public PathControllerBase {
 public:
  /// Throws std::invalid_argument if the path cannot be planned with this calibration.
  ScheduleController(PathSpec spec, BinaryCalibration calibration);
  ControllerOutputs step(const ControllerInputs& inputs) override;
  void reset() override;
  const char* name() const override { return "open_loop_schedule"; }
  const SwitchSchedule& schedule() const { return schedule_; }

 private:
  SwitchSchedule schedule_;
};

struct PathFollowingGains {
  double lookahead = 0.1;               ///< line-of-sight distance Delta [m]
  double cross_track_integral = 0.002;  ///< ILOS integral gain [1/s]
  double heading_gain = 0.5;            ///< share of the course error corrected per period (0..1)
  double fix_gain = 0.3;                ///< camera blend: p += gain (fix - p)
  double min_pulse = 0.5;               ///< shortest half-period worth switching [s]
  double search_window = 0.15;          ///< nearest-point search ahead of the progress point [m]
  double imu_timeout = 0.5;             ///< IMU older than this: heading dead-reckoned [s]
  double fix_timeout = 5.0;             ///< camera older than this: position dead-reckoned [s]
  double sensor_fault_timeout = 30.0;   ///< no IMU for this long: fault, motor stopped [s]
  double finish_tolerance = 0.02;       ///< open path: finished within this of its end [m]
  /// Throws std::invalid_argument naming the field and its range.
  void validate() const;
};

/// Closed loop. Estimator: heading from the IMU (dead-reckoned with the calibrated yaw rates
/// during an IMU dropout); position dead-reckoned with the calibrated body velocity of the
/// applied sign and pulled toward each camera fix. Guidance: integral line-of-sight to the
/// path. Actuation: one switching period at a time, the fraction of it at +omega chosen so the
/// mean yaw rate is the path's curvature feed-forward plus heading feedback.
class PathFollowingController : public PathControllerBase {
 public:
  PathFollowingController(PathSpec spec, BinaryCalibration calibration,
                          PathFollowingGains gains = {});
  ControllerOutputs step(const ControllerInputs& inputs) override;
  void reset() override;
  const char* name() const override { return "closed_loop_path_following"; }
  /// Estimated head position and heading (world).
  const Vec2& estimatedPosition() const { return position_; }
  double estimatedHeading() const { return heading_; }
  /// The sign actually applied from this step on, when another controller overrides this one's
  /// command (its dead reckoning then uses the true sign).
  void overrideAppliedSign(int sign) { applied_sign_ = sign >= 0 ? 1 : -1; }

 private:
  void onAnchored(const ControllerInputs& in, double heading) override;
  void predict(const ControllerInputs& in);
  void startPeriod(double time);
  double courseError(const Vec2& position, double course, double progress) const;

  PathFollowingGains gains_;
  Vec2 position_ = Vec2::Zero();
  double heading_ = 0.0;
  double last_time_ = 0.0, last_step_time_ = 0.0;
  double last_imu_time_ = 0.0, last_fix_time_ = 0.0;
  int applied_sign_ = 1;
  double progress_s_ = 0.0;
  double cross_track_integral_ = 0.0;
  double period_start_ = 0.0, plus_duration_ = 0.0;
  int turn_direction_ = 0;  ///< hysteresis for a goal behind the robot
};

}  // namespace flagella::control
