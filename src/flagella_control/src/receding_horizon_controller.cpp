#include "flagella_control/receding_horizon_controller.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "flagella_control/validation.h"

namespace flagella::control {
namespace {

constexpr int kMaxHorizon = 3;
constexpr int kMatchBack = 2;              // plan periods searched behind the expected one
constexpr int kMatchAhead = 6;             // and ahead of it
constexpr double kRescaleStep = 0.01;      // the horizon's model follows the estimate in 1 % steps
constexpr double kMaxStep = 1.0;           // [s] longer gaps between steps are not integrated
constexpr double kSearchBackPath = 0.02;   // [m] path window of the predicted error: behind the
constexpr double kSearchAheadPath = 0.15;  // progress point and ahead (a horizon's motion)
const char* const kGains = "receding horizon";

}  // namespace

void RecedingHorizonGains::validate() const {
  requireInRange(kGains, "horizon [periods]", horizon, 1, kMaxHorizon);
  requireInRange(kGains, "duty_steps", duty_steps, 1, 200);
  requireInRange(kGains, "heading_weight [m/rad]", heading_weight, 0.0, 10.0);
  requireInRange(kGains, "fallback_distance [m]", fallback_distance, 1e-4, 10.0);
  requireInRange(kGains, "adaptation_forgetting", adaptation_forgetting, 0.0, 1.0);
  requireInRange(kGains, "adaptation_prior [rad]", adaptation_prior, 1e-6, 10.0);
  requireInRange(kGains, "path_weight", path_weight, 0.0, 1e3);
}

RecedingHorizonController::RecedingHorizonController(PathSpec spec, BinaryCalibration calibration,
                                                     RecedingHorizonGains gains,
                                                     PathFollowingGains fallback,
                                                     TrackingBoundOptions plan_options)
    : PathControllerBase(spec, calibration),
      gains_(gains),
      inner_(spec, calibration, fallback),
      model_(calibration),
      active_(model_) {
  gains_.validate();
  // The plan: the bound's schedule of the smallest RMS error with a max error within 5 % of the
  // max bound (the schedule of the smallest RMS alone cut the triangle's corners by 25 mm where
  // 18 mm are possible), in the frame the path is anchored in at the start (0, heading 0);
  // moved rigidly onto the world path at anchoring.
  const Path frame_path = anchorPath(spec_, calibration_, Vec2::Zero(), 0.0);
  bound_ = computeTrackingBound(frame_path, spec_.laps, calibration_, plan_options);
  const TrackingBound& bound = bound_;
  if (!bound.plan.complete)
    throw std::invalid_argument("receding horizon: no schedule completes the path (plan)");
  const double T = calibration_.switch_period;
  samples_per_period_ =
      std::max(1, static_cast<int>(std::lround(T / plan_options.sample_interval)));
  frame_start_ = frame_path.at(0.0).position;
  frame_tangent_ = frame_path.at(0.0).tangent;
  PlanState state;
  state.position = frame_start_;
  state.heading = frame_tangent_ - calibration_.advance_angle;
  plan_.push_back(state);  // sample 0: the start
  int sign = 0;
  double dead = 0.0;
  for (double plus : bound.plan.plus_durations) {
    ModelMotion motion;
    for (int m = 1; m <= samples_per_period_; ++m) {
      motion = model_.until(state.heading, sign, dead, plus, T * m / samples_per_period_);
      plan_.push_back({state.position + motion.displacement, state.heading + motion.turn});
    }
    state = plan_.back();
    sign = plus < T ? -1 : 1;
    dead = motion.dead_remaining;
  }
  plan_world_ = plan_;
}

void RecedingHorizonController::reset() {
  resetBase();
  inner_.reset();
  plan_anchored_ = false;
  base_ = 0;
  use_fallback_ = true;
  applied_sign_ = 0;
  planned_periods_ = fallback_periods_ = 0;
  predicted_turn_ = sum_mp_ = sum_pp_ = 0.0;
  response_scale_ = 1.0;
  active_ = model_;
}

void RecedingHorizonController::anchorPlan() {
  const PathPoint start = world_path_.at(0.0);
  const double rotation = start.tangent - frame_tangent_;
  const Eigen::Rotation2Dd R(rotation);
  for (size_t i = 0; i < plan_.size(); ++i) {
    plan_world_[i].position = start.position + R * (plan_[i].position - frame_start_);
    plan_world_[i].heading = plan_[i].heading + rotation;
  }
  plan_anchored_ = true;
}

double RecedingHorizonController::sequenceCost(const Vec2& position, double heading, int sign,
                                               double dead, int base, double elapsed, int depth,
                                               double& first_plus) const {
  // docs/model.md 7.5: squared distance of the predicted head path to the plan's, sample by
  // sample, plus the heading error at each period's end (weighted as a distance). The first
  // period may be under way (`elapsed` seconds into it, +omega still held): then only switch
  // times from now on are candidates, and the samples still to come are compared.
  const double T = calibration_.switch_period;
  const int last = static_cast<int>(plan_world_.size()) - 1;
  const PlanState& end = plan_world_[std::min(base + samples_per_period_, last)];
  double best = std::numeric_limits<double>::infinity();
  for (int k = 0; k <= gains_.duty_steps; ++k) {
    const double plus = T * k / gains_.duty_steps;
    if (plus < elapsed) continue;
    double cost = 0.0;
    ModelMotion motion;
    for (int m = 1; m <= samples_per_period_; ++m) {
      const double t = T * m / samples_per_period_;
      if (t <= elapsed) continue;
      motion = active_.until(heading, sign, dead, plus - elapsed, t - elapsed);
      const Vec2& target = plan_world_[std::min(base + m, last)].position;
      const Vec2 predicted = position + motion.displacement;
      cost += (predicted - target).squaredNorm();
      if (gains_.path_weight > 0.0) {
        const double e =
            world_path_
                .project(predicted, progress_ - kSearchBackPath, progress_ + kSearchAheadPath)
                .distance;
        cost += gains_.path_weight * e * e;
      }
    }
    const double heading_error =
        gains_.heading_weight * wrapAngle(heading + motion.turn - end.heading);
    cost += samples_per_period_ * heading_error * heading_error;
    if (cost >= best) continue;
    if (depth + 1 < gains_.horizon) {
      double unused = 0.0;
      cost +=
          sequenceCost(position + motion.displacement, heading + motion.turn, plus < T ? -1 : 1,
                       motion.dead_remaining, base + samples_per_period_, 0.0, depth + 1, unused);
    }
    if (cost < best) {
      best = cost;
      first_plus = plus;
    }
  }
  return best;
}

double RecedingHorizonController::deadTimeLeft(double time) const {
  // The model's dead time after the last switch the controller made (at the start: the motor
  // starts, a switch too).
  return std::max(0.0, active_.deadTime() - (time - last_switch_time_));
}

void RecedingHorizonController::replanAtFix(double time) {
  // A camera fix within the + part of a planned period: choose its switch time again from the
  // better estimate (docs/model.md 7.5).
  const double elapsed = time - period_start_;
  if (use_fallback_ || elapsed <= 0.0 || elapsed >= plus_) return;
  progress_ = status_.progress * totalLength();
  sequenceCost(inner_.estimatedPosition(), inner_.estimatedHeading(), +1, deadTimeLeft(time), base_,
               elapsed, 0, plus_);
}

void RecedingHorizonController::adaptModel() {
  // docs/model.md 7.5: least squares of the measured turn per period on the calibrated one,
  // with forgetting and a prior of 1; the drift per period is not the signs' and is removed.
  const double heading = inner_.estimatedHeading();
  const double measured = wrapAngle(heading - decided_heading_) - model_.driftPerPeriod();
  decided_heading_ = heading;
  const double lambda = gains_.adaptation_forgetting;
  const double prior = gains_.adaptation_prior * gains_.adaptation_prior;
  sum_mp_ = lambda * sum_mp_ + measured * predicted_turn_;
  sum_pp_ = lambda * sum_pp_ + predicted_turn_ * predicted_turn_;
  predicted_turn_ = 0.0;
  const double scale = (sum_mp_ + prior) / (sum_pp_ + prior);
  if (!gains_.adapt || !std::isfinite(scale) || scale <= 0.0) return;
  if (std::abs(scale - response_scale_) > kRescaleStep * response_scale_) {
    response_scale_ = scale;
    active_ = model_.scaled(scale);
  }
}

void RecedingHorizonController::decide(double time) {
  // Where on the plan the robot is: the nearest period start of the plan in position and
  // heading, in a window about where the last match and the time since put it. (Beginning a new
  // period at every camera fix instead, matched to any plan sample, was tried: RMS 16 mm
  // against 4.4 mm on the square.)
  const int M = samples_per_period_;
  const int expected =
      base_ +
      static_cast<int>(std::lround((time - period_start_) / calibration_.switch_period * M));
  period_start_ = time;
  progress_ = status_.progress * totalLength();
  if (time - adapted_at_ >= calibration_.switch_period) {
    adapted_at_ = time;
    adaptModel();
  }
  const Vec2& p = inner_.estimatedPosition();
  const double heading = inner_.estimatedHeading();
  const int last_start = static_cast<int>(plan_world_.size()) - 1 - M;  // the last period's
  int best = -1;
  double best_d2 = std::numeric_limits<double>::infinity();
  const int from = std::max(0, expected - kMatchBack * M);
  const int to = std::min(last_start, expected + kMatchAhead * M);
  for (int i = from - from % M; i <= to; i += M) {
    const double dh = gains_.heading_weight * wrapAngle(heading - plan_world_[i].heading);
    const double d2 = (p - plan_world_[i].position).squaredNorm() + dh * dh;
    if (d2 < best_d2) {
      best_d2 = d2;
      best = i;
    }
  }
  use_fallback_ = best < 0 || std::sqrt(best_d2) > gains_.fallback_distance;
  if (use_fallback_) {
    ++fallback_periods_;
    base_ = std::clamp(expected, 0, std::max(0, last_start));
    return;
  }
  base_ = best;
  sequenceCost(p, heading, applied_sign_, deadTimeLeft(time), base_, 0.0, 0, plus_);
  ++planned_periods_;
}

ControllerOutputs RecedingHorizonController::step(const ControllerInputs& in) {
  ControllerOutputs out = inner_.step(in);
  status_ = inner_.status();
  if (!status_.anchored || out.mode != ControllerMode::Running) return out;
  if (!plan_anchored_) {
    world_path_ = inner_.worldPath();  // once, at anchoring
    anchorPlan();
    decided_heading_ = inner_.estimatedHeading();
    last_step_time_ = last_switch_time_ = adapted_at_ = period_start_ = in.time;
    base_ = 0;
    decide(in.time);
  } else if (in.time - period_start_ >= calibration_.switch_period) {
    decide(in.time);
  } else if (in.position_valid && gains_.replan_at_fix) {
    replanAtFix(in.time);
  }
  int sign = out.motor_command >= 0.0 ? 1 : -1;
  if (!use_fallback_) {
    sign = in.time - period_start_ < plus_ ? 1 : -1;
    inner_.overrideAppliedSign(sign);
    out.motor_command = sign * calibration_.omega;
  }
  // The calibrated turn of what was held since the last step (none within the dead time).
  const double dt = std::clamp(in.time - last_step_time_, 0.0, kMaxStep);
  last_step_time_ = in.time;
  if (in.time - last_switch_time_ >= model_.deadTime())
    predicted_turn_ += model_.yawRate(applied_sign_) * dt;
  if (sign != applied_sign_) last_switch_time_ = in.time;
  applied_sign_ = sign;
  return out;
}

}  // namespace flagella::control
