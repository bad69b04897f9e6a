// The mass-transformer closed loop (docs/model.md 7.4); see the header for the design.
#include "flagella_control/mass_transformer_controller.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "flagella_control/heading.h"
#include "flagella_control/validation.h"

namespace flagella::control {

namespace {
constexpr double kMinCosElevation = 0.25;  // gain schedule limit of the slider loop

BuckleScheduleKind otherSchedule(BuckleScheduleKind kind) {
  return kind == BuckleScheduleKind::Relax ? BuckleScheduleKind::ThreeLevel
                                           : BuckleScheduleKind::Relax;
}
}  // namespace

const char* steeringModeName(SteeringMode mode) {
  switch (mode) {
    case SteeringMode::Waiting:
      return "waiting";
    case SteeringMode::Cruise:
      return "cruise";
    case SteeringMode::BuckleTurn:
      return "buckle_turn";
    case SteeringMode::MassTransformer:
      return "mass_transformer";
    case SteeringMode::Finished:
      return "finished";
    case SteeringMode::Fault:
      return "fault";
  }
  return "unknown";
}

MassTransformerController::MassTransformerController(WaypointMission mission,
                                                     SteeringCalibration calibration,
                                                     SteeringGains gains)
    : mission_(std::move(mission)), calibration_(std::move(calibration)), gains_(gains) {
  mission_.validate();
  calibration_.validate();
  gains_.validate();
  // cycle_pitch divides by the up_per_slider of each schedule it may take a cycle from.
  const auto require_up_per_slider = [&](BuckleScheduleKind kind) {
    if (calibration_.schedule(kind).up_per_slider == 0.0)
      throw std::invalid_argument(
          std::string("steering gains: cycle_pitch needs a calibration with the ") +
          scheduleName(kind) +
          " schedule's up_per_slider (flagella_steer_calibrate --slider-pulses)");
  };
  if (gains_.cycle_pitch) {
    require_up_per_slider(gains_.schedule);
    if (gains_.mixed_schedules) require_up_per_slider(otherSchedule(gains_.schedule));
  }
  pitch_model_ = PitchModelEstimator(calibration_.pitch_rate_per_slider, calibration_.park_position,
                                     gains_.pitch_forgetting_time);
  world_points_.resize(mission_.points.size(), Vec3::Zero());
  reset();
}

void MassTransformerController::reset() {
  status_ = SteeringStatus{};
  anchored_ = course_pending_ = false;
  course_until_ = 0.0;
  course_origin_ = Vec3::Zero();
  last_time_ = last_imu_time_ = last_fix_time_ = 0.0;
  last_motor_ = 0.0;
  last_slider_ = calibration_.park_position;
  position_ = Vec3::Zero();
  direction_ = direction_stage_ = lean_ = Vec3::UnitX();
  holdoff_until_ = 0.0;
  top_since_ = lean_azimuth_ = sweep_rate_ = 0.0;
  last_fix_ = course_velocity_ = Vec3::Zero();
  has_fix_ = false;
  flip_sign_ = 1.0;
  elevation_ = roll_ = shaft_ = 0.0;
  wanted_ = Vec3::UnitX();
  slider_integral_ = 0.0;
  slider_lag_ = calibration_.park_position;
  model_crab_ = learn_after_ = pitching_since_ = 0.0;
  closest_ = INFINITY;
  turn_side_ = 0.0;
  course_axis_ = Vec3::UnitX();
  cycle_start_ = next_cycle_allowed_ = 0.0;
  status_.park_estimate = calibration_.park_position;
  cycle_before_ = Vec3::UnitX();
  cycle_pred_up_ = 0.0;
  cycle_to_measure_ = false;
  cycle_chi_ = cycle_size_ = cycle_offset_ = size_log_ = 0.0;
  schedule_ = calibration_.schedule(gains_.schedule);
  other_schedule_ = calibration_.schedule(otherSchedule(gains_.schedule));
  other_size_log_ = 0.0;
  status_.pulse_omega = schedule_.pulse_omega;
  trim_.reset();
  pitch_model_.reset();
  last_retrim_ = cycle_up_ = cycle_elevation_ = 0.0;
  within_since_ = aligned_since_ = 0.0;
  stall_reference_ = INFINITY;
  reorient_until_ = 0.0;
  reorient_up_ = reorient_left_ = reorient_motor_ = 1.0;
}

ControllerOutputs MassTransformerController::output(double motor, double slider,
                                                    ControllerMode mode) const {
  ControllerOutputs out;
  out.motor_command = motor;
  out.slider_valid = true;
  out.slider_position = slider;
  out.mode = mode;
  return out;
}

void MassTransformerController::guide(double time) {
  const int count = static_cast<int>(world_points_.size());
  // A waypoint counts as reached within reach_fraction of the tolerance, or within
  // pass_fraction of it once the distance grows again (the closest approach has passed): the
  // estimate's error would otherwise eat the margin.
  while (status_.waypoint < count) {
    const double distance = (world_points_[status_.waypoint] - position_).norm();
    closest_ = std::min(closest_, distance);
    const bool close = distance <= gains_.reach_fraction * mission_.tolerance;
    const bool passing = distance <= gains_.pass_fraction * mission_.tolerance &&
                         distance > closest_ + gains_.pass_margin;
    if (!close && !passing) break;
    ++status_.waypoint;
    ++status_.reached;
    closest_ = INFINITY;
    turn_side_ = 0.0;  // the next waypoint's side is its own
  }
  if (status_.waypoint >= count) return;
  const Vec3 to_go = world_points_[status_.waypoint] - position_;
  status_.distance = to_go.norm();
  wanted_ = to_go / status_.distance;
  status_.azimuth_error = wrapAngle(azimuthOf(wanted_) - azimuthOf(direction_) - status_.crab);
  const double leg_elevation =
      std::clamp(elevationOf(wanted_), -gains_.max_elevation, gains_.max_elevation);
  // A turn at elevation starts beyond `large_turn` (or beyond `blocked_turn` toward a side
  // buckle cycles cannot turn to), not while pitching back from the last one.
  const double abs_error = std::abs(status_.azimuth_error);
  const int side = status_.azimuth_error > 0.0 ? 1 : -1;
  status_.turn_possible = turnPossible(0.0, side);
  // Stalled: the error beyond stall_error and not shrinking by stall_progress for stall_time
  // (measured from when it went beyond, or last shrank by that much).
  if (abs_error <= gains_.stall_error || status_.flipping) {
    aligned_since_ = time;
    stall_reference_ = INFINITY;
  } else if (abs_error < stall_reference_ - gains_.stall_progress) {
    aligned_since_ = time;
    stall_reference_ = abs_error;
  }
  const bool stalled = gains_.stall_time > 0.0 && time - aligned_since_ > gains_.stall_time;
  if (!sliderAtPark() && !status_.flipping && time >= holdoff_until_ &&
      (abs_error > gains_.large_turn || stalled ||
       (!status_.turn_possible && abs_error > gains_.blocked_turn))) {
    status_.flipping = true;
    ++status_.flips;
    // Pitch up unless the leg clearly dives; kept for the whole turn.
    flip_sign_ = leg_elevation < -gains_.tilt_mode_threshold ? -1.0 : 1.0;
  }
  // At elevation: pitch back down once the direction of travel points the wanted way.
  const bool was_at_top = status_.at_top;
  status_.at_top =
      status_.flipping && std::abs(elevation_) > gains_.flip_elevation - gains_.top_margin;
  if (status_.at_top && !was_at_top) top_since_ = time;
  const double predicted = lean_azimuth_ + sweep_rate_ * gains_.exit_delay + status_.crab;
  const bool pointing = std::abs(wrapAngle(azimuthOf(wanted_) - predicted)) < gains_.exit_window;
  const bool too_long = status_.at_top && time - top_since_ > gains_.max_turn_time;
  if (status_.at_top && (pointing || too_long)) {
    status_.flipping = status_.at_top = false;
    holdoff_until_ = time + gains_.descent_holdoff;
    if (!pointing) ++status_.gave_up;
  }
  status_.target_elevation = status_.flipping ? flip_sign_ * gains_.flip_elevation : leg_elevation;
}

bool MassTransformerController::turnPossible(double up, double left) const {
  return schedule_.bestTurn(up, left) > gains_.min_turn_share * schedule_.deflection;
}

double MassTransformerController::motorCommand(double time) {
  if (gains_.reorient) return reorientCommand(time);
  const double cruise = calibration_.cruise_omega;
  if (status_.in_cycle) {
    const double s = time - cycle_start_;
    if (s < schedule_.cycleDuration()) return schedule_.omegaAt(s, cruise);
    status_.in_cycle = false;
    cycle_elevation_ += cycle_up_;  // the pitch model sees the cycle's turn as its own
    next_cycle_allowed_ = time + gains_.settle_time;
    status_.cycle_offset = 0.0;
    cycle_to_measure_ = gains_.cycle_pitch;
  }
  if (gains_.cycle_pitch) return cyclePitchCommand(time);
  // Buckle cycles turn the direction of travel toward the waypoint, in azimuth and elevation
  // (the cycle's turn is a direction in the plane normal to travel chosen by the flagellum's
  // phase), not during a turn at elevation or the pitch back from it.
  const double up_error = status_.target_elevation - elevation_;
  const double left_error = status_.azimuth_error * std::cos(elevation_);
  const double size = std::hypot(up_error, left_error);
  const bool wants_turn = size > gains_.turn_threshold && size < gains_.max_buckle_error &&
                          !status_.flipping && time >= holdoff_until_ && !status_.imu_stale &&
                          time >= next_cycle_allowed_;
  if (wants_turn) {
    const double du = up_error / size, dl = left_error / size;
    // Start when this phase turns toward the error within the window of the best phase.
    double up = 0.0, left = 0.0;
    schedule_.predictedTurn(roll_, shaft_, up, left);
    const double threshold =
        schedule_.bestTurn(du, dl) - schedule_.deflection * (1.0 - std::cos(gains_.phase_window));
    if (turnPossible(du, dl) && up * du + left * dl >= threshold) {
      status_.in_cycle = true;
      ++status_.cycles;
      cycle_start_ = time;
      cycle_up_ = up;
      return schedule_.omegaAt(0.0, cruise);
    }
  }
  return cruise;
}

double MassTransformerController::sliderCommand(double dt) {
  const double lo = sliderLow(), hi = sliderHigh();
  if (status_.imu_stale) return last_slider_;  // no tilt: hold
  if (sliderAtPark()) {  // at the park estimate, offset by a cycle or a turn in place
    const double command = status_.park_estimate + status_.cycle_offset;
    status_.slider_saturated = command > hi || command < lo;
    return std::clamp(command, lo, hi);
  }
  status_.neutral = neutral();
  status_.steer_offset = 0.0;
  // Held through a buckle cycle and its settling: at the neutral, where a cycle's turn was
  // calibrated (no couple); the elevation loop waits.
  const bool held = gains_.hold_in_cycle && (status_.in_cycle || last_time_ < next_cycle_allowed_);
  const double command = held ? neutral() : neutral() + loopOffset(dt, lo, hi);
  status_.slider_saturated = command > hi || command < lo;
  return std::clamp(command, lo, hi);
}

double MassTransformerController::loopOffset(double dt, double lo, double hi) {
  const double error = status_.target_elevation - elevation_;
  // The elevation loop takes the slider once the error has stayed beyond tilt_mode_threshold for
  // tilt_entry_share of the flagellum's rotation period at cruise (the head's elevation wobbles
  // with it: shorter excursions are wobble), until it is within tilt_exit_threshold.
  if (std::abs(error) <= gains_.tilt_mode_threshold) within_since_ = last_time_;
  const double entry = gains_.tilt_entry_share * 2.0 * M_PI / calibration_.cruise_omega;
  const bool beyond = last_time_ - within_since_ >= entry && last_time_ > within_since_;
  if ((beyond || status_.flipping) && !status_.pitching) {
    status_.pitching = true;
    pitching_since_ = last_time_;
  }
  if (std::abs(error) < gains_.tilt_exit_threshold && !status_.flipping) status_.pitching = false;
  // The course shows a pitching offset's crab for a while: no neutral learning until it is gone.
  if (status_.pitching)
    learn_after_ = last_time_ + gains_.crab_lag_time + gains_.course_filter_time;
  if (gains_.steer_by_offset && !status_.pitching) return status_.steer_offset = steerOffset();
  return pitchOffset(error, dt, lo, hi);
}

double MassTransformerController::steerOffset() {
  // The offset whose crab points the course at the waypoint (straight on while the start
  // frame's course is measured).
  double wanted_crab =
      course_pending_ ? 0.0 : wrapAngle(azimuthOf(wanted_) - azimuthOf(direction_));
  // A waypoint behind: keep turning to the side chosen while it was behind (the error's sign
  // flips as the waypoint passes behind, and the turn would stall between the two). A waypoint
  // within 90 deg, or a new one, is turned to the short way.
  if (std::abs(wanted_crab) > M_PI / 2 && turn_side_ != 0.0 && wanted_crab * turn_side_ < 0.0)
    wanted_crab += turn_side_ * 2.0 * M_PI;
  turn_side_ = std::abs(wanted_crab) > M_PI / 2 ? std::copysign(1.0, wanted_crab) : 0.0;
  return std::clamp(wanted_crab / calibration_.crab_per_slider, -gains_.max_steer_offset,
                    gains_.max_steer_offset);
}

double MassTransformerController::pitchOffset(double error, double dt, double lo, double hi) {
  const double k = calibration_.pitch_rate_per_slider *
                   std::max(std::cos(elevation_), kMinCosElevation);  // [rad/s per m]
  // [m]; no more than the offset that pitches at max_pitch_rate.
  const double limit = gains_.max_pitch_rate / k;
  double proportional = std::clamp(error / (k * gains_.tilt_time_constant), -limit, limit);
  // With offset steering, never below min_pitch_offset: smaller offsets mostly turn the robot
  // (docs/model.md 7.4), so a loop lingering near its target would steer instead of pitch.
  if (gains_.steer_by_offset && std::abs(proportional) < gains_.min_pitch_offset)
    proportional = std::copysign(std::min(gains_.min_pitch_offset, limit), error);
  const double increment = proportional * dt / gains_.tilt_integral_time;
  const double unclamped = neutral() + proportional;
  // Anti-windup: integrate only while the output is inside the travel or the step moves it in.
  // With offset steering the neutral is learnt from the course instead: the pitching offsets
  // are hundreds of micrometres, and a few seconds of them would move it by tens. Only a loop
  // that cannot settle for tilt_integral_delay (a neutral far off) integrates.
  const bool integrate =
      !gains_.steer_by_offset || last_time_ - pitching_since_ > gains_.tilt_integral_delay;
  if (integrate && (unclamped < hi || increment < 0.0) && (unclamped > lo || increment > 0.0))
    slider_integral_ += increment;
  return proportional;
}

ControllerOutputs MassTransformerController::step(const ControllerInputs& in) {
  if (status_.mode == SteeringMode::Finished || status_.mode == SteeringMode::Fault)
    return output(
        0.0, calibration_.park_position,
        status_.mode == SteeringMode::Finished ? ControllerMode::Finished : ControllerMode::Fault);
  if (!anchored_) {
    if (!in.imu_valid) return output(0.0, calibration_.park_position, ControllerMode::Idle);
    anchor(in);
  }
  const double dt = std::max(0.0, in.time - last_time_);
  last_time_ = in.time;
  estimate(in, dt);
  if (in.time - last_imu_time_ > gains_.sensor_fault_timeout) {
    status_.mode = SteeringMode::Fault;
    status_.message = "no IMU sample within sensor_fault_timeout: motor stopped";
    last_motor_ = 0.0;
    return output(0.0, calibration_.park_position, ControllerMode::Fault);
  }
  if (course_pending_) {
    const double cruise = calibration_.cruise_omega;
    if (in.time < course_until_) {  // straight and level: no cycles, the slider holds 0 deg
      status_.target_elevation = 0.0;
      const double slider = sliderCommand(dt);
      status_.elevation = elevation_;
      last_motor_ = cruise;
      last_slider_ = slider;
      return output(cruise, slider, ControllerMode::Running);
    }
    // x along the net displacement (the course), or the head axis if the robot barely moved.
    course_pending_ = false;
    trimNeutral();
    const Vec3 moved(position_.x() - course_origin_.x(), position_.y() - course_origin_.y(), 0.0);
    const double expected = calibration_.cruise_speed * mission_.course_time;
    const bool moved_enough = moved.norm() > gains_.min_course_speed * expected;
    const double azimuth = moved_enough ? azimuthOf(moved) : azimuthOf(direction_);
    if (moved_enough && !gains_.steer_by_offset)
      setCrab(wrapAngle(azimuth - azimuthOf(direction_)));
    anchorWaypoints(course_origin_, azimuth);
  }
  guide(in.time);
  retrimNeutral(in.time);
  if (gains_.cycle_pitch) learnPark();
  if (status_.waypoint >= static_cast<int>(world_points_.size())) {
    status_.mode = SteeringMode::Finished;
    status_.message = "all waypoints reached";
    status_.in_cycle = false;
    last_motor_ = 0.0;
    return output(0.0, calibration_.park_position, ControllerMode::Finished);
  }
  const double motor = motorCommand(in.time);
  const double slider = sliderCommand(dt);
  status_.elevation = elevation_;
  if (status_.reorienting) {
    status_.mode = SteeringMode::MassTransformer;
    status_.message = "turning in place by the slider's offset and the motor's direction";
  } else if (status_.flipping || status_.pitching) {
    status_.mode = SteeringMode::MassTransformer;
    status_.message = status_.at_top     ? "turning at elevation until the azimuth points the way"
                      : status_.flipping ? "pitching to turn at elevation"
                                         : "changing elevation";
  } else if (!gains_.reorient &&
             (status_.in_cycle || std::abs(status_.azimuth_error) > gains_.turn_threshold)) {
    status_.mode = SteeringMode::BuckleTurn;
    status_.message = status_.in_cycle ? "buckle cycle" : "waiting for the flagellum's phase";
  } else {
    status_.mode = SteeringMode::Cruise;
    status_.message =
        gains_.steer_by_offset ? "cruising, steered by the slider's offset" : "cruising";
  }
  if (status_.imu_stale) status_.message = "IMU stale: no new buckle cycle, slider held";
  last_motor_ = motor;
  last_slider_ = slider;
  return output(motor, slider, ControllerMode::Running);
}

}  // namespace flagella::control
