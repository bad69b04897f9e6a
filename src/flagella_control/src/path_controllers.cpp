#include "flagella_control/path_controllers.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "flagella_control/validation.h"

namespace flagella::control {
namespace {

constexpr double kAnchorWait = 1.0;              // [s] wait this long for a first camera fix
constexpr double kMaxPredictionStep = 1.0;       // [s] longer gaps between steps are not integrated
constexpr double kSearchBack = 0.02;             // [m] projection window behind the progress point
constexpr double kBehindThreshold = 0.5 * M_PI;  // course error that makes a turn "committed"
constexpr double kReleaseThreshold = 0.25 * M_PI;
constexpr int kDutySteps = 40;  // candidate shares of +omega per switching period
const char* const kGains = "path following";

// Direction of the net motion over a period with `plus` seconds at +omega, relative to the
// heading at its start.
double chordAngle(const BinaryCalibration& c, double plus) {
  const Vec2 d = predictPeriod(c, 0.0, plus).displacement;
  return std::atan2(d.y(), d.x());
}

const SignResponse& response(const BinaryCalibration& c, int sign) {
  return sign >= 0 ? c.plus : c.minus;
}

}  // namespace

Path anchorPath(const PathSpec& spec, const BinaryCalibration& c, const Vec2& start,
                double start_heading) {
  if (spec.frame == PathFrame::World) return spec.path;
  // Start frame: origin at the head, x along the direction of advance of switching begun now.
  return spec.path.transformed(start, start_heading + c.advance_angle);
}

// ---- common part ------------------------------------------------------------------------------

PathControllerBase::PathControllerBase(PathSpec spec, BinaryCalibration calibration)
    : spec_(std::move(spec)), calibration_(std::move(calibration)) {
  calibration_.validate();
  if (spec_.path.empty()) throw std::invalid_argument("path following: the path is empty");
}

void PathControllerBase::resetBase() {
  status_ = PathStatus{};
  have_fix_ = false;
  first_imu_time_ = -1.0;
}

bool PathControllerBase::anchorIfNeeded(const ControllerInputs& in) {
  if (status_.anchored) return true;
  if (in.position_valid) {
    have_fix_ = true;
    first_fix_ = Vec2(in.position[0], in.position[1]);
  }
  if (!in.imu_valid) return false;
  if (first_imu_time_ < 0.0) first_imu_time_ = in.time;
  if (!have_fix_ && in.time - first_imu_time_ < kAnchorWait) {
    status_.message = "waiting for the first camera fix";
    return false;
  }
  const double heading = headingFromQuaternion(in.orientation);
  world_path_ = anchorPath(spec_, calibration_, have_fix_ ? first_fix_ : Vec2::Zero(), heading);
  status_.anchored = true;
  status_.message = have_fix_ ? "running" : "running (no camera fix at the start: anchored at 0)";
  start_time_ = in.time;
  onAnchored(in, heading);
  return true;
}

ControllerOutputs PathControllerBase::idle() const {
  ControllerOutputs out;
  out.motor_command = 0.0;
  out.mode = ControllerMode::Idle;
  return out;
}

ControllerOutputs PathControllerBase::finished() {
  status_.progress = 1.0;
  status_.message = "path complete";
  ControllerOutputs out;
  out.motor_command = 0.0;
  out.mode = ControllerMode::Finished;
  return out;
}

double PathControllerBase::totalLength() const {
  return world_path_.length() * (world_path_.closed() ? spec_.laps : 1);
}

// ---- open loop --------------------------------------------------------------------------------

ScheduleController::ScheduleController(PathSpec spec, BinaryCalibration calibration)
    : PathControllerBase(std::move(spec), std::move(calibration)),
      schedule_(planSchedule(spec_.path, calibration_, spec_.laps)) {
  if (spec_.frame == PathFrame::Start) {
    const PathPoint first = spec_.path.at(0.0);
    if (first.position.norm() > 1e-3 || std::abs(wrapAngle(first.tangent)) > 1e-3)
      throw std::invalid_argument(
          "open loop: a start-frame path must begin at the origin heading along +x (the "
          "schedule assumes the robot starts on the path's first element)");
  }
}

void ScheduleController::reset() { resetBase(); }

ControllerOutputs ScheduleController::step(const ControllerInputs& in) {
  if (status_.mode_finished) return finished();
  if (!anchorIfNeeded(in)) return idle();
  const double t = in.time - start_time_;
  const SwitchInterval* interval = schedule_.intervalAt(t);
  if (!interval) {
    status_.mode_finished = true;
    return finished();
  }
  // Progress and errors from the schedule position only: open loop ignores the sensors.
  status_.element = interval->element;
  status_.progress = std::clamp(t / schedule_.duration, 0.0, 1.0);
  ControllerOutputs out;
  out.motor_command = interval->sign * calibration_.omega;
  out.mode = ControllerMode::Running;
  return out;
}

// ---- closed loop ------------------------------------------------------------------------------

void PathFollowingGains::validate() const {
  requireInRange(kGains, "lookahead [m]", lookahead, 1e-3, 10.0);
  requireInRange(kGains, "cross_track_integral [1/s]", cross_track_integral, 0.0, 10.0);
  requireInRange(kGains, "heading_gain [fraction of the course error per period]", heading_gain,
                 0.0, 1.0);
  requireInRange(kGains, "fix_gain", fix_gain, 0.0, 1.0);
  requireInRange(kGains, "min_pulse [s]", min_pulse, 0.0, 100.0);
  requireInRange(kGains, "search_window [m]", search_window, 1e-3, 100.0);
  requireInRange(kGains, "imu_timeout [s]", imu_timeout, 1e-3, 1e3);
  requireInRange(kGains, "fix_timeout [s]", fix_timeout, 1e-3, 1e4);
  requireInRange(kGains, "sensor_fault_timeout [s]", sensor_fault_timeout, 1e-3, 1e4);
  requireInRange(kGains, "finish_tolerance [m]", finish_tolerance, 0.0, 10.0);
}

PathFollowingController::PathFollowingController(PathSpec spec, BinaryCalibration calibration,
                                                 PathFollowingGains gains)
    : PathControllerBase(std::move(spec), std::move(calibration)), gains_(gains) {
  gains_.validate();
  if (2.0 * gains_.min_pulse > calibration_.switch_period)
    throw std::invalid_argument("path following: min_pulse must be at most half the switch period");
}

void PathFollowingController::reset() {
  resetBase();
  progress_s_ = 0.0;
  cross_track_integral_ = 0.0;
  turn_direction_ = 0;
  applied_sign_ = 1;
}

void PathFollowingController::onAnchored(const ControllerInputs& in, double heading) {
  position_ = have_fix_ ? first_fix_ : Vec2::Zero();
  heading_ = heading;
  last_time_ = last_imu_time_ = last_step_time_ = in.time;
  last_fix_time_ = have_fix_ ? in.time : in.time - 2.0 * gains_.fix_timeout;
  progress_s_ = 0.0;
  plus_duration_ = 0.5 * calibration_.switch_period;  // as if a straight period came before
  startPeriod(in.time);
}

void PathFollowingController::predict(const ControllerInputs& in) {
  const double dt = std::clamp(in.time - last_time_, 0.0, kMaxPredictionStep);
  last_time_ = in.time;
  const SignResponse& r = response(calibration_, applied_sign_);
  // Dead reckoning with the calibrated steady motion of the sign applied since the last step.
  position_ += Eigen::Rotation2Dd(heading_) * Vec2(r.body_velocity[0], r.body_velocity[1]) * dt;
  if (in.imu_valid) {
    heading_ = headingFromQuaternion(in.orientation);
    last_imu_time_ = in.time;
  } else {
    heading_ = wrapAngle(heading_ + r.yaw_rate * dt);
  }
  if (in.position_valid) {
    position_ += gains_.fix_gain * (Vec2(in.position[0], in.position[1]) - position_);
    last_fix_time_ = in.time;
  }
  status_.imu_stale = in.time - last_imu_time_ > gains_.imu_timeout;
  status_.fix_stale = in.time - last_fix_time_ > gains_.fix_timeout;
}

double PathFollowingController::courseError(const Vec2& position, double course,
                                            double progress) const {
  // Pure pursuit of a carrot `lookahead` ahead of the nearest point, shifted across the path by
  // the integral of the cross-track error (removes a steady offset).
  // Beyond the end of the run (the last lap of a closed path ends at its start) the carrot
  // runs on along the final direction, so the robot crosses the end instead of circling it.
  const double total = totalLength();
  const double s = std::min(progress + gains_.lookahead, total);
  PathPoint carrot_point = world_path_.at(world_path_.closed() && s >= total ? total - 1e-9 : s);
  carrot_point.position +=
      std::max(0.0, progress + gains_.lookahead - total) * unitVector(carrot_point.tangent);
  const Vec2 normal = unitVector(carrot_point.tangent + 0.5 * M_PI);
  const Vec2 carrot =
      carrot_point.position - gains_.cross_track_integral * cross_track_integral_ * normal;
  const Vec2 to_carrot = carrot - position;
  return wrapAngle(std::atan2(to_carrot.y(), to_carrot.x()) - course);
}

void PathFollowingController::startPeriod(double time) {
  period_start_ = time;
  const double T = calibration_.switch_period;
  // Course error of a straight (equal halves) period begun now.
  const double error = courseError(position_, heading_ + calibration_.advance_angle, progress_s_);
  status_.heading_error = error;
  // A goal behind the robot: hold the sign that turns the way we started (no flip-flopping).
  if (std::abs(error) > kBehindThreshold) {
    if (turn_direction_ == 0) turn_direction_ = error > 0 ? 1 : -1;
    plus_duration_ = (turn_direction_ > 0) == (calibration_.plus.yaw_rate > 0) ? T : 0.0;
    return;
  }
  if (std::abs(error) < kReleaseThreshold) turn_direction_ = 0;
  // One-period look-ahead: for each candidate share of +omega, predict where the calibrated
  // model puts the robot at the end of the period (including the sideways slip of unequal
  // halves) and its course error there; aim for (1 - heading_gain) of today's error.
  const double target = (1.0 - gains_.heading_gain) * error;
  const double total = totalLength();
  double best_cost = std::numeric_limits<double>::infinity();
  for (int k = 0; k <= kDutySteps; ++k) {
    const double plus = T * k / kDutySteps;
    if ((plus > 0.0 && plus < gains_.min_pulse) || (T - plus > 0.0 && T - plus < gains_.min_pulse))
      continue;
    const PeriodMotion m = predictPeriod(calibration_, heading_, plus);
    const Vec2 end = position_ + m.displacement;
    const double s = world_path_
                         .project(end, progress_s_ - kSearchBack,
                                  std::min(progress_s_ + gains_.search_window, total))
                         .s;
    // Its course error at the end if the same share were kept (a steady turn slips sideways).
    const double course = heading_ + m.turn + chordAngle(calibration_, plus);
    const double e = courseError(end, course, std::max(s, progress_s_)) - target;
    if (e * e < best_cost) {
      best_cost = e * e;
      plus_duration_ = plus;
    }
  }
}

ControllerOutputs PathFollowingController::step(const ControllerInputs& in) {
  if (status_.mode_finished) return finished();
  if (!anchorIfNeeded(in)) return idle();
  predict(in);
  if (in.time - last_imu_time_ > gains_.sensor_fault_timeout) {
    status_.message = "fault: no IMU sample within sensor_fault_timeout; motor stopped";
    ControllerOutputs out;
    out.mode = ControllerMode::Fault;
    return out;
  }
  // Progress: the nearest point in a window around the last progress (never moves back).
  const double total = totalLength();
  const PathProjection proj = world_path_.project(
      position_, progress_s_ - kSearchBack, std::min(progress_s_ + gains_.search_window, total));
  progress_s_ = std::max(progress_s_, proj.s);
  status_.element = proj.point.element;
  status_.cross_track = proj.cross_track;
  status_.progress = std::clamp(progress_s_ / total, 0.0, 1.0);
  const double dt = in.time - last_step_time_;
  last_step_time_ = in.time;
  if (proj.distance < gains_.lookahead && dt > 0.0 && dt < kMaxPredictionStep)
    cross_track_integral_ += proj.cross_track * dt;
  // Anti-windup: the carrot never moves further across than one lookahead.
  const double limit =
      gains_.cross_track_integral > 0 ? gains_.lookahead / gains_.cross_track_integral : 0.0;
  cross_track_integral_ = std::clamp(cross_track_integral_, -limit, limit);

  // Done: the whole run's arclength covered (an open path: reaching its end).
  // or being past the end point along the path's final direction, near the end.
  const PathPoint end = world_path_.at(world_path_.closed() ? total - 1e-9 : total);
  const bool done = progress_s_ >= total - gains_.finish_tolerance ||
                    ((position_ - end.position).dot(unitVector(end.tangent)) >= 0.0 &&
                     progress_s_ >= total - gains_.lookahead);
  if (done) {
    status_.mode_finished = true;
    return finished();
  }
  if (in.time - period_start_ >= calibration_.switch_period) startPeriod(in.time);
  applied_sign_ = in.time - period_start_ < plus_duration_ ? 1 : -1;
  status_.message = status_.imu_stale   ? "running: IMU dropout, heading dead-reckoned"
                    : status_.fix_stale ? "running: no recent camera fix, position dead-reckoned"
                                        : "running";
  ControllerOutputs out;
  out.motor_command = applied_sign_ * calibration_.omega;
  out.mode = ControllerMode::Running;
  return out;
}

}  // namespace flagella::control
