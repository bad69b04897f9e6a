// The mass-transformer closed loop (docs/model.md 7.4): 3-D waypoint following of the helical
// robot with its two inputs, the motor rate and the internal slider. ControllerCore contract:
// fixed step (on every IMU sample), ROS-free, no heap allocation in step().
//
// Estimator: the head axis from the IMU (two cascaded first-order filters remove the head's
// wobble) and the crab angle between it and the course over ground: the robot does not swim
// along its head axis (measured in the simulator: its course runs about 30 deg to the right of
// it, docs/model.md 7.4), so the direction of travel is the axis turned by a crab angle learnt
// from the camera fixes (the course from their filtered velocity); its elevation from the
// accelerometer (filtered), the head roll and the shaft angle (integral of the commanded rate) for
// the flagellum's phase, and the position dead-reckoned at the calibrated cruise speed and pulled
// toward each camera fix. Guidance: toward the current waypoint; reached within the mission's
// tolerance. Modes:
//  - cruise: omega_3 below the buckling threshold, slider holding the target elevation;
//  - buckle-to-turn: azimuth error above `turn_threshold`: buckle cycles (schedule relax or
//    three_level), each started when the flagellum's phase makes the calibrated turn of the
//    cycle (a constant part plus a part set by the phase) go to the wanted side, then a settling
//    time before the next; a side the cycles cannot turn to is left to the turn at elevation;
//  - mass-transformer: an elevation change above `tilt_mode_threshold`, or a turn at elevation
//    for an azimuth error above `large_turn` (`blocked_turn` toward a side buckle cycles cannot
//    turn to). The slider pitches the robot up (down for a diving leg) to `flip_elevation`;
//    after a pitch-up the robot's azimuth precesses (measured in the simulator: 2-4 deg/s to the
//    right for about 40 s, 90-150 deg in all, then it stalls; docs/model.md 7.4). The controller
//    cruises there and pitches back down to the leg's elevation once the direction of travel,
//    carried on at its measured azimuth rate for `exit_delay` (the turn goes on while it pitches
//    down), points within `exit_window` of the wanted azimuth, or after `max_turn_time`; a turn
//    still missing is taken by the next pitch-up after `descent_holdoff`. Feedback only: no model
//    of the turn, either side.
// The slider loop: PI on the elevation error from the accelerometer, gain scheduled by the
// calibrated pitch rate per slider metre and cos(elevation), anti-windup at the travel limits;
// its integral finds the slider position that cancels an unknown COM-COV offset.
#pragma once

#include <cstdint>
#include <vector>

#include "flagella_control/controller_core.h"
#include "flagella_control/head_attitude.h"
#include "flagella_control/steering_calibration.h"
#include "flagella_control/waypoint_mission.h"

namespace flagella::control {

struct SteeringGains {
  BuckleScheduleKind schedule = BuckleScheduleKind::Relax;
  double heading_filter_time = 2.5;   ///< each of the two direction filters [s]
  double tilt_filter_time = 0.5;      ///< accelerometer elevation filter [s]
  double turn_threshold = 0.07;       ///< azimuth error that calls for buckle turns [rad]
  double large_turn = 0.8;            ///< azimuth error that calls for a turn at elevation [rad]
  double blocked_turn = 0.8;          ///< the same toward a side buckle cycles cannot turn to
  double flip_elevation = 1.05;       ///< elevation of that turn (60 deg) [rad]
  double top_margin = 0.17;           ///< within this of flip_elevation the robot is turning
  double lean_filter_time = 1.0;      ///< filter of the head axis while turning at elevation [s]
  double exit_window = 0.26;          ///< pitch back down this near the wanted azimuth [rad]
  double exit_delay = 3.0;            ///< the azimuth is extrapolated this far at its rate [s]
  double sweep_filter_time = 5.0;     ///< filter of that azimuth rate [s]
  double max_turn_time = 60.0;        ///< longest stay at elevation per pitch-up [s]
  double descent_holdoff = 25.0;      ///< after pitching back: no new turn at elevation [s]
  double tilt_mode_threshold = 0.17;  ///< elevation error reported as mass-transformer mode [rad]
  double phase_window = 0.35;         ///< a cycle starts within this phase of the best one [rad]
  /// Buckle turns to a side only if the best cycle turns that way by at least this share of the
  /// calibrated phase-dependent deflection (else the constant part wins: no turn that way).
  double min_turn_share = 0.25;
  double settle_time = 6.0;            ///< after a cycle, before the next [s]
  double max_elevation = 0.6;          ///< limit of a leg's target elevation (34 deg) [rad]
  double tilt_time_constant = 6.0;     ///< closed-loop time constant of the slider loop [s]
  double max_pitch_rate = 0.15;        ///< the slider loop asks for no faster pitch [rad/s]
  double tilt_integral_time = 12.0;    ///< its integral time [s]
  double slider_margin = 2e-4;         ///< keep off the hard stops by this [m]
  double fix_gain = 0.3;               ///< position: p += gain (fix - p)
  double course_filter_time = 20.0;    ///< velocity from camera fixes, filtered [s]
  double crab_filter_time = 30.0;      ///< crab angle (course minus axis azimuth), filtered [s]
  double max_crab = 1.0;               ///< the crab estimate is held within +-this [rad]
  double min_course_speed = 0.5;       ///< course used above this share of the cruise speed
  double imu_timeout = 0.5;            ///< IMU older than this: no new cycles, slider held [s]
  double fix_timeout = 20.0;           ///< camera older than this: fix reported stale [s]
  double sensor_fault_timeout = 10.0;  ///< no IMU for this long: fault, motor stopped [s]
  /// Throws std::invalid_argument naming the field and its range.
  void validate() const;
};

enum class SteeringMode : std::uint8_t {
  Waiting = 0,  ///< for the first IMU sample (or measuring the course of the start frame)
  Cruise = 1,
  BuckleTurn = 2,
  MassTransformer = 3,
  Finished = 4,
  Fault = 5
};
const char* steeringModeName(SteeringMode mode);

struct SteeringStatus {
  SteeringMode mode = SteeringMode::Waiting;
  int waypoint = 0;               ///< index of the waypoint being approached
  int reached = 0;                ///< waypoints reached so far
  double distance = 0.0;          ///< estimated distance to the waypoint [m]
  double azimuth_error = 0.0;     ///< wanted minus estimated azimuth of travel [rad]
  double elevation = 0.0;         ///< estimated elevation of travel (accelerometer) [rad]
  double target_elevation = 0.0;  ///< of the slider loop [rad]
  bool in_cycle = false;          ///< a buckle cycle is running
  bool turn_possible = true;      ///< a buckle cycle can turn toward the wanted side
  long cycles = 0;                ///< buckle cycles started
  bool flipping = false;          ///< a turn at elevation is under way
  bool at_top = false;            ///< ... and the robot is at that elevation, turning
  long flips = 0;                 ///< turns at elevation started
  long gave_up = 0;               ///< turns at elevation ended by max_turn_time
  bool imu_stale = false, fix_stale = false, slider_saturated = false;
  double crab = 0.0;  ///< course minus head-axis azimuth, as learnt [rad]
  const char* message = "waiting for the first IMU sample";  ///< static text
};

class MassTransformerController : public ControllerCore {
 public:
  /// Throws std::invalid_argument for an invalid mission, calibration or gains.
  MassTransformerController(WaypointMission mission, SteeringCalibration calibration,
                            SteeringGains gains = {});
  ControllerOutputs step(const ControllerInputs& inputs) override;
  void reset() override;
  const char* name() const override { return "mass_transformer"; }

  const SteeringStatus& status() const { return status_; }
  /// Waypoints in the world (valid once anchored: status().mode != Waiting).
  const std::vector<Vec3>& waypoints() const { return world_points_; }
  const Vec3& estimatedPosition() const { return position_; }
  const Vec3& estimatedDirection() const { return direction_; }
  const SteeringCalibration& calibration() const { return calibration_; }
  const WaypointMission& mission() const { return mission_; }
  const SteeringGains& gains() const { return gains_; }

 private:
  void anchor(const ControllerInputs& in);
  void anchorWaypoints(const Vec3& origin, double azimuth);
  void estimate(const ControllerInputs& in, double dt);
  void guide(double time);
  void learnCrab(const Vec3& fix, double time);
  void setCrab(double crab);  ///< within +-max_crab
  double motorCommand(double time);
  bool turnPossible(int side) const;
  double sliderCommand(double dt);
  ControllerOutputs output(double motor, double slider, ControllerMode mode) const;

  WaypointMission mission_;
  SteeringCalibration calibration_;
  SteeringGains gains_;
  const BuckleSchedule* schedule_ = nullptr;
  std::vector<Vec3> world_points_;
  SteeringStatus status_;

  bool anchored_ = false;
  bool course_pending_ = false;  ///< cruising straight to measure the start frame's x
  double course_until_ = 0.0;
  Vec3 course_origin_ = Vec3::Zero();
  double last_time_ = 0.0, last_imu_time_ = 0.0, last_fix_time_ = 0.0;
  double last_motor_ = 0.0, last_slider_ = 0.0;
  Vec3 position_ = Vec3::Zero();
  Vec3 direction_ = Vec3::UnitX(), direction_stage_ = Vec3::UnitX();
  Vec3 lean_ = Vec3::UnitX();  ///< lightly filtered head axis (followed at elevation)
  Vec3 last_fix_ = Vec3::Zero(), course_velocity_ = Vec3::Zero();
  bool has_fix_ = false;
  double top_since_ = 0.0;  ///< when the robot reached the turn's elevation [s]
  double lean_azimuth_ = 0.0, sweep_rate_ = 0.0;  ///< [rad], its rate [rad/s]
  double holdoff_until_ = 0.0;
  double flip_sign_ = 1.0;  ///< +1: the turn at elevation pitches up, -1: down
  double elevation_ = 0.0;  ///< filtered accelerometer elevation of travel
  double roll_ = 0.0, shaft_ = 0.0;
  Vec3 wanted_ = Vec3::UnitX();   ///< unit direction to the waypoint
  double slider_integral_ = 0.0;  ///< [m] from the park position
  double cycle_start_ = 0.0, next_cycle_allowed_ = 0.0;
};

}  // namespace flagella::control
