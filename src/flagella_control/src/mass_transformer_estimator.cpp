// The mass-transformer controller's estimator (docs/model.md 7.4; the header has the design):
// anchoring the waypoints on the start frame's course, the head axis, elevation and position
// from the IMU, accelerometer and camera fixes, the crab angle and the slider's neutral (learnt
// from the course, trimmed and re-trimmed from the head's pitch).
#include <algorithm>
#include <cmath>

#include "flagella_control/heading.h"
#include "flagella_control/mass_transformer_controller.h"

namespace flagella::control {

namespace {
constexpr double kMinGravityReading = 4.0;  // [m/s^2]: below, the accelerometer gives no tilt

// One step of a first-order filter with time constant tau.
double blend(double dt, double tau) { return tau > 0.0 ? std::min(1.0, dt / tau) : 1.0; }
}  // namespace

void MassTransformerController::anchor(const ControllerInputs& in) {
  const HeadAttitude attitude = attitudeFromQuaternion(in.orientation);
  direction_ = direction_stage_ = lean_ = course_axis_ = attitude.forward;
  lean_azimuth_ = azimuthOf(lean_);
  roll_ = attitude.roll;
  const double a = travelElevationFromAcceleration(in.linear_acceleration, kMinGravityReading);
  elevation_ = std::isfinite(a) ? a : elevationOf(attitude.forward);
  if (in.position_valid) {
    position_ = last_fix_ = Vec3(in.position[0], in.position[1], in.position[2]);
    last_fix_time_ = in.time;
    has_fix_ = true;
  }
  anchored_ = true;
  last_time_ = last_imu_time_ = within_since_ = aligned_since_ = in.time;
  next_cycle_allowed_ = in.time + gains_.settle_time;
  if (mission_.frame == PathFrame::Start && mission_.course_time > 0.0) {
    // The start frame's x is the course of a straight, level cruise (waypoint_mission.h).
    course_pending_ = true;
    course_until_ = in.time + mission_.course_time;
    course_origin_ = position_;
    status_.message = "measuring the course of the start frame";
    return;
  }
  anchorWaypoints(position_, azimuthOf(attitude.forward));
}

void MassTransformerController::anchorWaypoints(const Vec3& origin, double azimuth) {
  for (std::size_t i = 0; i < world_points_.size(); ++i)  // sized at construction
    world_points_[i] = worldWaypoint(mission_, mission_.points[i], origin, azimuth);
  status_.mode = SteeringMode::Cruise;
}

void MassTransformerController::estimate(const ControllerInputs& in, double dt) {
  // Shaft angle relative to the head: the integral of the rate commanded last step.
  shaft_ += last_motor_ * dt;
  // The course follows the slider's offset with a lag; the crab it gives (docs/model.md 7.4).
  // Only offsets of the steering range count: the crab does not grow in proportion to the
  // hundreds of micrometres of a pitching offset (measured: it saturates).
  const double offset =
      std::clamp(last_slider_ - neutral(), -gains_.max_steer_offset, gains_.max_steer_offset);
  slider_lag_ += blend(dt, gains_.crab_lag_time) * (neutral() + offset - slider_lag_);
  if (gains_.steer_by_offset) setCrab(offsetCrab());
  // Position: dead reckoning at the calibrated speed (scaled by the rate below the threshold,
  // 0 when stopped, backward when the motor runs reversed), then the camera fix.
  const double rate =
      std::clamp(last_motor_, -calibration_.cruise_omega, calibration_.cruise_omega);
  const Vec3 travel = directionFrom(azimuthOf(direction_) + status_.crab, elevationOf(direction_));
  position_ += calibration_.cruise_speed * (rate / calibration_.cruise_omega) * dt * travel;
  if (in.position_valid) {
    const Vec3 fix(in.position[0], in.position[1], in.position[2]);
    position_ += gains_.fix_gain * (fix - position_);
    learnCrab(fix, in.time);
    last_fix_time_ = in.time;
  }
  if (in.imu_valid) {
    const HeadAttitude attitude = attitudeFromQuaternion(in.orientation);
    const double k = blend(dt, gains_.heading_filter_time);
    direction_stage_ = (direction_stage_ + k * (attitude.forward - direction_stage_)).normalized();
    direction_ = (direction_ + k * (direction_stage_ - direction_)).normalized();
    lean_ = (lean_ + blend(dt, gains_.lean_filter_time) * (attitude.forward - lean_)).normalized();
    const double azimuth = azimuthOf(lean_);
    if (dt > 0.0)
      sweep_rate_ += blend(dt, gains_.sweep_filter_time) *
                     (wrapAngle(azimuth - lean_azimuth_) / dt - sweep_rate_);
    lean_azimuth_ = azimuth;
    // During a turn at elevation and while pitching back from it, the slow direction filter
    // lags the turn: it follows the lightly filtered axis.
    if (status_.flipping || in.time < holdoff_until_) direction_ = direction_stage_ = lean_;
    roll_ = attitude.roll;
    const double head_elevation = elevationOf(attitude.forward);
    if (course_pending_)
      trim_.add(in.time - last_imu_time_, head_elevation, last_slider_,
                calibration_.pitch_rate_per_slider);
    // Less the calibrated up-turns of the buckle cycles so far: the slider did not pitch those.
    pitch_model_.add(in.time - last_imu_time_, head_elevation - cycle_elevation_, last_slider_);
    last_imu_time_ = in.time;
    const double a = travelElevationFromAcceleration(in.linear_acceleration, kMinGravityReading);
    if (std::isfinite(a)) elevation_ += blend(dt, gains_.tilt_filter_time) * (a - elevation_);
  }
  status_.imu_stale = in.time - last_imu_time_ > gains_.imu_timeout;
  status_.fix_stale = in.time - last_fix_time_ > gains_.fix_timeout;
}

void MassTransformerController::learnCrab(const Vec3& fix, double time) {
  // Course over ground from the fixes' velocity; the crab angle is its azimuth minus the head
  // axis's, learnt while cruising near level (not during or just after a turn at elevation).
  const double dt = time - last_fix_time_;
  if (has_fix_ && dt > 0.0) {
    course_velocity_ +=
        blend(dt, gains_.course_filter_time) * ((fix - last_fix_) / dt - course_velocity_);
    const Vec3 horizontal(course_velocity_.x(), course_velocity_.y(), 0.0);
    const bool cruising = !status_.flipping && time >= holdoff_until_ &&
                          std::abs(elevation_) < gains_.max_elevation + gains_.top_margin;
    const bool moving = horizontal.norm() > gains_.min_course_speed * calibration_.cruise_speed;
    if (gains_.steer_by_offset) {
      // The head axis and the offset's crab, filtered as the course is, to compare with it
      // (a turning axis would otherwise show as crab).
      const double k = blend(dt, gains_.course_filter_time);
      course_axis_ = (course_axis_ + k * (direction_ - course_axis_)).normalized();
      model_crab_ += k * (status_.crab - model_crab_);
      const double measured = wrapAngle(azimuthOf(horizontal) - azimuthOf(course_axis_));
      if (cruising && moving && time >= learn_after_) learnNeutral(measured, dt);
    } else if (cruising && moving) {
      const double crab = wrapAngle(azimuthOf(horizontal) - azimuthOf(direction_));
      setCrab(status_.crab + blend(dt, gains_.crab_filter_time) * wrapAngle(crab - status_.crab));
    }
  }
  last_fix_ = fix;
  has_fix_ = true;
}

void MassTransformerController::learnNeutral(double measured_crab, double dt) {
  // crab = c (x_lag - x_n): a course further left than the model's means a neutral further right.
  const double error =
      std::clamp(wrapAngle(model_crab_ - measured_crab), -gains_.max_crab, gains_.max_crab);
  slider_integral_ += blend(dt, gains_.neutral_filter_time) * error / calibration_.crab_per_slider;
}

void MassTransformerController::trimNeutral() {
  // The course shows neutral errors in proportion only up to max_crab / |crab_per_slider|
  // (about 44 um; learnNeutral clamps beyond): a larger error, seen in how the head pitched
  // during the start frame's straight cruise (neutral_trim.h), is taken at once. Smaller ones
  // are left to the course, the finer measure (1.3 deg of crab per um against 0.5 deg/min of
  // pitch; the two neutrals differ by about 6 um on the nominal robot).
  const double estimate = trim_.neutral();
  status_.trim_neutral = estimate;
  if (!gains_.trim_neutral || !std::isfinite(estimate)) return;
  // cycle_pitch, reorient: park is the pitch neutral less the robot's own pitching (calibrated).
  if (sliderAtPark())
    status_.park_estimate = std::clamp(estimate - ownPitchOffset(), sliderLow(), sliderHigh());
  const double shift = estimate - neutral();
  const double reach = gains_.max_crab / std::abs(calibration_.crab_per_slider);
  if (std::abs(shift) <= reach || std::abs(shift) <= gains_.trim_sigmas * trim_.standardError())
    return;
  takeNeutral(estimate);
  slider_lag_ = neutral();
  status_.trimmed = true;
}

void MassTransformerController::takeNeutral(double estimate) {
  slider_integral_ = std::clamp(estimate, sliderLow(), sliderHigh()) - calibration_.park_position;
  pitching_since_ = last_time_;  // the elevation loop's integral waits again
}

void MassTransformerController::retrimNeutral(double time) {
  // The neutral the mission's pitch gives, with the pitch rate learnt alongside (a model wrong
  // in it biases the start frame's trim, docs/model.md 7.4), taken when off by more than
  // retrim_threshold; the course refines it between re-trims.
  if (time - last_retrim_ < gains_.retrim_interval ||
      pitch_model_.seconds() < gains_.retrim_interval)
    return;
  double alpha = NAN, estimate = NAN, standard_error = NAN;
  if (!pitch_model_.estimate(alpha, estimate, standard_error)) return;
  status_.pitch_gain = alpha;
  status_.pitch_neutral = estimate;
  const double shift = std::abs(estimate - neutral());
  if (!gains_.retrim_neutral || shift <= gains_.retrim_threshold ||
      !(shift > gains_.trim_sigmas * standard_error))
    return;
  takeNeutral(estimate);
  last_retrim_ = time;
  ++status_.retrims;
}

double MassTransformerController::offsetCrab() const {
  return calibration_.crab_per_slider * (slider_lag_ - neutral());
}

void MassTransformerController::setCrab(double crab) {
  status_.crab = std::clamp(crab, -gains_.max_crab, gains_.max_crab);
}

}  // namespace flagella::control
