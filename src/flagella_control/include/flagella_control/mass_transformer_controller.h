// The mass-transformer closed loop (docs/model.md 7.4): 3-D waypoint following of the helical
// robot with its two inputs, the motor rate and the internal slider. ControllerCore contract:
// fixed step (on every IMU sample), ROS-free, no heap allocation in step().
//
// What the simulated robot does (docs/model.md 7.4): micrometres of slider offset from the
// neutral position (no COM-COV couple) make its course run at a crab angle to the head axis
// (calibrated `crab_per_slider`, about 1.3 deg per um) and turn the axis the same way while it
// pitches (right and up, or left and down); hundreds of micrometres pitch it; a buckle cycle
// turns the direction of travel by a few degrees toward a direction set by the flagellum's phase.
//
// Estimator: the head axis from the IMU (two cascaded first-order filters remove the head's
// wobble); the course is that axis turned by the crab angle (with `steer_by_offset`, the crab
// the lagged slider offset gives; without, a constant crab learnt from the camera fixes); the
// elevation from the accelerometer (filtered), the head roll and the shaft angle (integral of
// the commanded rate) for the flagellum's phase, and the position dead-reckoned at the
// calibrated cruise speed and pulled toward each camera fix. Guidance: toward the current
// waypoint; reached within `reach_fraction` of the mission's tolerance, or within
// `pass_fraction` of it once the estimated distance grows again. Modes:
//  - cruise: omega_3 below the buckling threshold; with `steer_by_offset` the slider sits at the
//    offset whose crab points the course at the waypoint (at most `max_steer_offset`; to one side
//    once the waypoint is behind); the neutral is learnt by comparing the camera's course with
//    the crab the offset should give (`neutral_filter_time`), and (`trim_neutral`) trimmed
//    once from the head's pitch during the start frame's straight cruise when further off than
//    the course can show (neutral_trim.h), and (`retrim_neutral`) re-trimmed from the pitch
//    over the whole mission, where the pitching offsets also give the pitch rate
//    (pitch_model_estimator.h);
//  - buckle-to-turn: an error of the direction of travel (azimuth and elevation) between
//    `turn_threshold` and `max_buckle_error`: buckle cycles (schedule relax or three_level), each
//    started when the flagellum's phase points the calibrated turn of the cycle (a constant part
//    plus a part set by the phase) along the error, then a settling time before the next;
//  - mass-transformer: the elevation error beyond `tilt_mode_threshold` for `tilt_entry_share` of
//    the flagellum's rotation period, until it is within
//    `tilt_exit_threshold`: PI on the accelerometer's elevation, gain scheduled by the calibrated
//    pitch rate per slider metre and cos(elevation), anti-windup at the travel limits (with
//    `steer_by_offset`: at least `min_pitch_offset`, and the integral only after
//    `tilt_integral_delay` without settling); or a turn at elevation for an azimuth error above
//    `large_turn` (`blocked_turn` toward a side buckle cycles cannot turn to; pi by default, for
//    the earlier design without offset steering 0.8), or for one beyond `stall_error` that has
//    not shrunk for `stall_time` (the offset does not turn the robot): the slider pitches the
//    robot up (down for a diving leg) to `flip_elevation`, where its azimuth precesses
//    (measured: 2-4 deg/s to the right for about 40 s), and back down once the direction of
//    travel, carried on at its measured azimuth rate for `exit_delay`, points within
//    `exit_window` of the wanted azimuth, or after `max_turn_time`; a turn still missing is
//    taken by the next pitch-up after `descent_holdoff`.
//  - turns in place (`reorient`, instead of buckle cycles and the slider loop): the slider held
//    `reorient_offset` off its park estimate with the motor at `reorient_omega` forward or
//    reversed; the offset pitches the robot either way and the turn that comes with the pitch
//    changes side with the motor's direction, so the four combinations turn the direction of
//    travel along the four diagonals (mass_transformer_reorient.cpp).
#pragma once

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "flagella_control/controller_core.h"
#include "flagella_control/head_attitude.h"
#include "flagella_control/neutral_trim.h"
#include "flagella_control/pitch_model_estimator.h"
#include "flagella_control/steering_calibration.h"
#include "flagella_control/waypoint_mission.h"

namespace flagella::control {

struct SteeringGains {
  BuckleScheduleKind schedule = BuckleScheduleKind::Relax;
  double heading_filter_time = 2.5;  ///< each of the two direction filters [s]
  double tilt_filter_time = 0.5;     ///< accelerometer elevation filter [s]
  double turn_threshold =
      0.07;  ///< error of the direction of travel that calls for buckle turns [rad]
  /// Buckle turns only below this error [rad]: larger ones are the slider's (buckled flagella
  /// are where the simulation is hardest, and a cycle turns by about 2 deg).
  double max_buckle_error = 0.35;
  /// Azimuth error that calls for a turn at elevation [rad]: pi (never) by default, since the
  /// slider's offset turns either way; 0.8 suits steering without it (steer_by_offset false).
  double large_turn = M_PI;
  double blocked_turn = M_PI;  ///< the same toward a side buckle cycles cannot turn to [rad]
  /// An azimuth error beyond stall_error that has not shrunk by stall_progress within
  /// stall_time (the slider's offset does not turn the robot, e.g. a model wrong in the crab)
  /// also starts a turn at elevation (0: never) [s].
  double stall_time = 90.0;
  double stall_error = 1.0;           ///< [rad]
  double stall_progress = 0.2;        ///< [rad]
  double flip_elevation = 1.05;       ///< elevation of that turn (60 deg) [rad]
  double top_margin = 0.17;           ///< within this of flip_elevation the robot is turning
  double lean_filter_time = 1.0;      ///< filter of the head axis while turning at elevation [s]
  double exit_window = 0.26;          ///< pitch back down this near the wanted azimuth [rad]
  double exit_delay = 3.0;            ///< the azimuth is extrapolated this far at its rate [s]
  double sweep_filter_time = 5.0;     ///< filter of that azimuth rate [s]
  double max_turn_time = 60.0;        ///< longest stay at elevation per pitch-up [s]
  double descent_holdoff = 25.0;      ///< after pitching back: no new turn at elevation [s]
  double tilt_mode_threshold = 0.17;  ///< elevation error reported as mass-transformer mode [rad]
  /// ... once it has stayed beyond for this share of the flagellum's rotation period at cruise
  /// (2 pi / cruise_omega, 7.6 s; the head's elevation wobbles with the rotation; 0: at once).
  double tilt_entry_share = 0.5;
  double phase_window = 0.35;  ///< a cycle starts within this phase of the best one [rad]
  /// Buckle turns to a side only if the best cycle turns that way by at least this share of the
  /// calibrated phase-dependent deflection (else the constant part wins: no turn that way).
  double min_turn_share = 0.25;
  double settle_time = 6.0;  ///< after a cycle, before the next [s]
  /// The slider at the neutral from a buckle cycle's start until its settle_time has passed (the
  /// elevation loop waits). On the source's robot (helical_steering_source.yaml) a cycle with
  /// the slider 50 um off park turned the robot 5-24 deg up besides its calibrated 10.6 deg by
  /// phase (README, "The source's steering robot").
  bool hold_in_cycle = false;
  /// The elevation by buckle cycles alone, through the slider (docs/model.md 7.4): the slider
  /// sits at the park estimate (no couple: the robot keeps its elevation) and is held off it
  /// through a cycle by the offset whose calibrated turn (up_per_slider) brings the predicted
  /// up-turn to the elevation error; the cycle's phase is chosen for the azimuth. Each cycle's
  /// measured turn corrects the park estimate (it starts at the start frame's trim). No slider
  /// loop, no turns at elevation. Needs a calibration with up_per_slider.
  bool cycle_pitch = false;
  double max_cycle_offset = 4e-5;  ///< largest such offset from the park estimate [m]
  double max_cycle_up = 0.35;      ///< largest up- or down-turn one cycle is asked for [rad]
  double park_learning = 0.5;      ///< share of a cycle's measured up-turn error corrected
  /// cycle_pitch: the turn per cycle learnt online (docs/model.md 7.4): after each settled cycle,
  /// the log of the turn's size over the predicted moves the learnt size gain by this share, and
  /// the phase offset moves by this share of the direction's error; with pulse_growth > 0 each
  /// cycle's pulse rate is also the one whose predicted turn by phase has the wanted size (at
  /// most max_cycle_turn); 0: off (the calibrated pulse, no learning). A model
  /// 20 % too stiff turns 2.3 deg instead of 22.7 at the calibrated pulse, and its phase offset
  /// is 1.4 rad off (README, "The source's steering robot").
  double turn_learning = 0.0;
  double max_cycle_turn = 0.4;  ///< turn learning: largest turn one cycle is sized for [rad]
  /// d ln(turn by phase) / d(pulse rate over the calibrated threshold) for sizing the cycles:
  /// 9.1 for three_level and 7.2 for relax between pulses of 1.25 and 1.5 omega_b held 6 s (the
  /// turn table) [1]; 0 (default): every cycle at the calibrated pulse, its turn as learnt (at
  /// 3 omega_b for 2 s the turn no longer grows so).
  double pulse_growth = 0.0;
  double min_pulse_factor = 1.1;  ///< turn learning keeps the pulse above this x omega_b [1]
  double max_pulse_factor = 2.0;  ///< ... and below this [1]
  /// cycle_pitch: each cycle by the schedule (relax or three_level) whose best phase comes
  /// nearer the wanted turn, both as calibrated (and learnt alike): on the source's robot, pulses
  /// of 3 omega_b for 2 s turn it 8.8 deg (relax) or 28.9 deg (three_level) by phase.
  bool mixed_schedules = false;
  /// Turns in place (docs/model.md 7.4): the slider offset +-reorient_offset from the park
  /// estimate with the motor at +-reorient_omega, the four combinations pitching and turning the
  /// robot along the four diagonals (up and right for a positive offset forward), held
  /// reorient_dwell each, while the direction of travel is off by more than reorient_enter and
  /// until it is within reorient_exit; cruise straight at the park estimate in between (no buckle
  /// cycles). Needs the slider's calibrated pitch rate; the park estimate as cycle_pitch's.
  bool reorient = false;
  double reorient_offset = 1.5e-3;   ///< slider offset from the park estimate [m]
  double reorient_omega = 2.0944;    ///< motor rate, either way (20 rpm) [rad/s]
  double reorient_dwell = 4.0;       ///< each combination held this long [s]
  double reorient_enter = 0.15;      ///< error of the direction of travel that starts it [rad]
  double reorient_exit = 0.07;       ///< ... and ends it [rad]
  double reorient_full_error = 0.3;  ///< the offset in full above this error, in proportion below
  double reorient_min_share = 0.3;   ///< ... but at least this share of it
  double reorient_balance = 0.4;     ///< a component below this share of the error alternates
  bool reorient_up_turns_right = true;  ///< forward, a positive offset turns the robot right
  double max_elevation = 0.6;           ///< limit of a leg's target elevation (34 deg) [rad]
  double tilt_time_constant = 6.0;      ///< closed-loop time constant of the slider loop [s]
  double max_pitch_rate = 0.15;         ///< the slider loop asks for no faster pitch [rad/s]
  double tilt_integral_time = 12.0;     ///< its integral time [s]
  double tilt_exit_threshold = 0.05;    ///< the elevation loop lets go below this error [rad]
  /// With offset steering the elevation loop integrates only after this long without settling
  /// (a neutral far off) [s]: short corrections would move the neutral by tens of micrometres.
  double tilt_integral_delay = 15.0;
  /// Azimuth steered by small slider offsets around the neutral (crab angle, see above); false:
  /// the slider only holds the elevation and the crab is learnt as a constant.
  bool steer_by_offset = true;
  double min_pitch_offset = 2e-4;  ///< with offset steering: the elevation loop's least offset [m]
  double crab_lag_time = 20.0;     ///< the course follows the offset with this lag [s]
  double max_steer_offset = 8e-5;  ///< largest steering offset from the neutral [m]
  double neutral_filter_time = 60.0;  ///< learning the neutral from the course [s]
  /// Trim: the neutral from the head's pitch while the start frame's course is measured
  /// (`course_time`), taken when it differs from the neutral by more than the course can show
  /// (max_crab / |crab_per_slider|) and by more than trim_sigmas standard errors. With
  /// tilt_entry_share 0.5: more missions complete with the right model, fewer waypoints reached
  /// with a wrong one (README, Results).
  bool trim_neutral = true;
  double trim_sigmas = 3.0;
  /// Re-trim: the neutral and the pitch rate learnt from the head's pitch over the whole mission
  /// (pitch_model_estimator.h, forgetting after pitch_forgetting_time); the neutral is set to the
  /// estimate when they differ by more than retrim_threshold and trim_sigmas standard errors of
  /// the estimate, at most every retrim_interval.
  bool retrim_neutral = true;
  double pitch_forgetting_time = 120.0;  ///< [s]
  double retrim_threshold = 8e-6;        ///< [m]
  double retrim_interval = 60.0;         ///< [s]
  double slider_margin = 2e-4;           ///< keep off the hard stops by this [m]
  double fix_gain = 0.3;                 ///< position: p += gain (fix - p)
  /// A waypoint is reached within this share of the mission's tolerance, or within
  /// pass_fraction of the tolerance once the estimated distance has grown by pass_margin past
  /// its minimum (below 1, the estimate's error cannot carry a pass out of the tolerance).
  double reach_fraction = 0.5;
  double pass_fraction = 1.0;
  double pass_margin = 1e-3;           ///< [m]
  double course_filter_time = 20.0;    ///< velocity from camera fixes, filtered [s]
  double crab_filter_time = 30.0;      ///< crab angle (course minus axis azimuth), filtered [s]
  double max_crab = 1.0;               ///< the crab estimate is held within +-this [rad]
  double min_course_speed = 0.5;       ///< course used above this share of the cruise speed
  double imu_timeout = 0.5;            ///< IMU older than this: no new cycles, slider held [s]
  double fix_timeout = 20.0;           ///< camera older than this: fix reported stale [s]
  double sensor_fault_timeout = 10.0;  ///< no IMU for this long: fault, motor stopped [s]
  /// Throws std::invalid_argument naming the field and its range.
  void validate() const;
  /// Sets a numeric gain by its field name (`steer_by_offset` takes 0 or 1); throws
  /// std::invalid_argument for an unknown name listing the known ones.
  void set(const std::string& name, double value);
  /// The names `set` knows.
  static std::vector<std::string> names();
  /// True for the on/off gains (0 or 1).
  static bool isFlag(const std::string& name);
  /// Reads a numeric gain by name (as `set`).
  double get(const std::string& name) const;
  /// Every gain with its value, unit and meaning, a line each (steering_gains.cpp).
  std::string table() const;
  /// Sets the gains a YAML file names: one top-level map `steering_gains:` of gain name: value
  /// (flags 0 or 1), as `set` (config/calibration/helical_steering_source_gains.yaml). Throws
  /// flagella::InputFileError naming the file and the field for an unreadable file, an unknown
  /// gain or a value that is not a number; ranges are checked by validate().
  void load(const std::string& path);
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
  double park_estimate = NAN;     ///< cycle_pitch: slider position of no couple [m]
  double cycle_offset = 0.0;      ///< cycle_pitch: the running cycle's slider offset [m]
  long park_updates = 0;          ///< cycle_pitch: cycles whose turn corrected the estimate
  double pulse_omega = NAN;       ///< cycle_pitch: the pulse rate of the next cycle [rad/s]
  double phase_shift = 0.0;       ///< cycle_pitch: learnt correction of the phase offset [rad]
  double turn_gain = 1.0;         ///< cycle_pitch: learnt turn size over the calibrated model's
  long turn_updates = 0;          ///< cycle_pitch: cycles whose turn corrected size gain or phase
  bool reorienting = false;       ///< reorient: turning in place
  long reorient_dwells = 0;       ///< reorient: combinations held so far
  bool turn_possible = true;      ///< a buckle cycle can turn toward the wanted side
  long cycles = 0;                ///< buckle cycles started
  bool flipping = false;          ///< a turn at elevation is under way
  bool at_top = false;            ///< ... and the robot is at that elevation, turning
  long flips = 0;                 ///< turns at elevation started
  long gave_up = 0;               ///< turns at elevation ended by max_turn_time
  bool imu_stale = false, fix_stale = false, slider_saturated = false;
  double crab = 0.0;  ///< course minus head-axis azimuth, as learnt (or set by the offset) [rad]
  bool pitching = false;       ///< the slider is changing the elevation
  double neutral = 0.0;        ///< the slider position estimated to give no couple [m]
  double steer_offset = 0.0;   ///< the steering offset from it [m]
  double trim_neutral = NAN;   ///< the neutral the start frame's pitch gave (NaN before) [m]
  bool trimmed = false;        ///< ... and it was taken
  double pitch_neutral = NAN;  ///< the neutral the mission's pitch gives (re-trim) [m]
  double pitch_gain = NAN;     ///< the pitch rate learnt over the calibrated one
  long retrims = 0;            ///< times the neutral was re-trimmed
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
  void learnNeutral(double measured_crab, double dt);
  double neutral() const { return calibration_.park_position + slider_integral_; }
  /// The robot's pitch neutral less park: the calibrated own pitching over the pitch rate [m].
  double ownPitchOffset() const {
    return -calibration_.park_pitch_rate / calibration_.pitch_rate_per_slider;
  }
  /// cycle_pitch: what a cycle of this schedule started at phase chi leaves of the wanted turn,
  /// with the slider offset (within max_cycle_offset) that adds to its phase up-turn what it
  /// lacks of the wanted up-turn [m], and its predicted turn (up, left) [rad].
  double cycleMiss(const BuckleSchedule& schedule, double chi, double wanted_up, double wanted_left,
                   double& offset, double& up, double& left) const;
  /// ... the least of that over the phases [rad].
  double bestMiss(const BuckleSchedule& schedule, double wanted_up, double wanted_left) const;
  /// cycle_pitch and reorient: the slider sits at the park estimate, offset only by a cycle or a
  /// turn in place (no slider loop, no turn at elevation).
  bool sliderAtPark() const { return gains_.cycle_pitch || gains_.reorient; }
  double cyclePitchCommand(double time);  ///< cycle_pitch: the motor command (cycles)
  double reorientCommand(double time);    ///< reorient: the motor command (turns in place)
  /// cycle_pitch: after a cycle has settled, its measured up-turn corrects the park estimate.
  void learnPark();
  /// cycle_pitch with turn_learning: after a cycle has settled, its measured turn corrects the
  /// learnt turn gain (size) and the phase offset (direction); true when the turn agreed with the
  /// prediction well enough for the park estimate to learn from its up-turn.
  bool learnTurn(double up, double left);
  /// cycle_pitch with turn_learning: the pulse rate (and the predicted turn) of the next cycle
  /// for a turn of this size [rad].
  void sizeCycle(double wanted, double size_log, BuckleSchedule& schedule) const;
  /// The slider's travel kept slider_margin off the hard stops [m].
  double sliderLow() const { return calibration_.slider_min + gains_.slider_margin; }
  double sliderHigh() const { return calibration_.slider_max - gains_.slider_margin; }
  void trimNeutral();  ///< at the end of the start frame's cruise (SteeringGains::trim_neutral)
  void retrimNeutral(double time);  ///< from the mission's pitch (SteeringGains::retrim_neutral)
  /// Sets the neutral to `estimate` within the slider's travel; the elevation loop's integral
  /// waits again (tilt_integral_delay).
  void takeNeutral(double estimate);
  double offsetCrab() const;  ///< the crab the lagged slider offset gives [rad]
  void setCrab(double crab);  ///< within +-max_crab
  double motorCommand(double time);
  /// A buckle cycle can turn along the unit direction (up, left) (min_turn_share).
  bool turnPossible(double up, double left) const;
  double sliderCommand(double dt);
  /// The slider's offset from the neutral the elevation loop or the offset steering asks for
  /// (its mode switching included) [m].
  double loopOffset(double dt, double lo, double hi);
  double steerOffset();  ///< steering offset from the neutral [m]
  /// Elevation loop's offset from the neutral [m] (its integral moves the neutral).
  double pitchOffset(double error, double dt, double lo, double hi);
  ControllerOutputs output(double motor, double slider, ControllerMode mode) const;

  WaypointMission mission_;
  SteeringCalibration calibration_;
  SteeringGains gains_;
  /// The gains' schedule as calibrated; with turn_learning sized for the next cycle (pulse rate,
  /// turn, offset's turn) and its phase offset as learnt (reset() restores the calibrated one).
  BuckleSchedule schedule_;
  /// mixed_schedules: the other schedule, learnt alike (swapped with schedule_ for a cycle).
  BuckleSchedule other_schedule_;
  double other_size_log_ = 0.0;
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
  double reorient_until_ = 0.0;                     ///< reorient: the held combination ends [s]
  double reorient_up_ = 1.0, reorient_left_ = 1.0;  ///< reorient: the combination's diagonal
  double reorient_motor_ = 1.0;                     ///< reorient: +1 forward, -1 reversed
  double flip_sign_ = 1.0;  ///< +1: the turn at elevation pitches up, -1: down
  double elevation_ = 0.0;  ///< filtered accelerometer elevation of travel
  double roll_ = 0.0, shaft_ = 0.0;
  Vec3 wanted_ = Vec3::UnitX();   ///< unit direction to the waypoint
  double slider_integral_ = 0.0;  ///< [m]: the neutral estimate minus the park position
  double slider_lag_ = 0.0;       ///< the slider command as the course follows it [m]
  double model_crab_ = 0.0;       ///< the offset's crab, filtered like the camera's course [rad]
  Vec3 course_axis_ = Vec3::UnitX();  ///< the head axis, filtered like the camera's course
  double learn_after_ = 0.0;          ///< no neutral learning before this time [s]
  double pitching_since_ = 0.0;       ///< the elevation loop took the slider then [s]
  double closest_ = INFINITY;         ///< estimated closest approach to the waypoint [m]
  /// Side the steering turns to while the waypoint is behind (+1 left, -1 right, 0 none).
  double turn_side_ = 0.0;
  double cycle_start_ = 0.0, next_cycle_allowed_ = 0.0;
  // cycle_pitch: the running cycle's start direction and predicted turn, to measure it after
  Vec3 cycle_before_ = Vec3::UnitX();
  double cycle_pred_up_ = 0.0;
  bool cycle_to_measure_ = false;
  // its predicted direction and size [rad], slider offset [m]
  double cycle_chi_ = 0.0, cycle_size_ = 0.0, cycle_offset_ = 0.0;
  double size_log_ = 0.0;       // turn learning: ln of the learnt turn size over the model's
  double within_since_ = 0.0;   ///< last time the elevation error was within tilt_mode_threshold
  double aligned_since_ = 0.0;  ///< the azimuth error last within stall_error or shrinking [s]
  double stall_reference_ = INFINITY;  ///< |azimuth error| then [rad]
  NeutralTrim trim_;                   ///< the neutral from the pitch of the start frame's cruise
  PitchModelEstimator pitch_model_;    ///< neutral and pitch rate from the mission's pitch
  double last_retrim_ = 0.0;           ///< [s]
  double cycle_up_ = 0.0;              ///< calibrated up-turn of the running buckle cycle [rad]
  double cycle_elevation_ = 0.0;       ///< ... summed over the cycles completed [rad]
};

}  // namespace flagella::control
