#include "flagella_control/switching_model.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>

#include "flagella_control/switch_planner.h"

namespace flagella::control {
namespace {

constexpr int kBisectionSteps = 60;  // dead time to far below a microsecond

}  // namespace

DeadTimeModel::DeadTimeModel(const BinaryCalibration& c)
    : plus_(c.plus),
      minus_(c.minus),
      period_(c.switch_period),
      drift_per_period_(c.heading_drift_per_period) {
  c.validate();
  fit(c.advance_per_period, c.advance_angle);
}

void DeadTimeModel::fit(double advance_per_period, double advance_angle) {
  advance_per_period_ = advance_per_period;
  advance_angle_ = advance_angle;
  // docs/model.md 7.5: the dead time tau solves |D(tau)| = advance per period, D the displacement
  // of one period of steady switching (+ half entered from -, - half from +), D decreasing in tau.
  const auto advance = [&](double tau) {
    return until(0.0, -1, 0.0, 0.5 * period_, period_, tau).displacement;
  };
  double lo = 0.0, hi = 0.5 * period_;
  if (advance(lo).norm() <= advance_per_period) {
    hi = 0.0;  // even without a dead time the model advances less than measured
  } else {
    for (int i = 0; i < kBisectionSteps; ++i) {
      const double mid = 0.5 * (lo + hi);
      (advance(mid).norm() > advance_per_period ? lo : hi) = mid;
    }
  }
  dead_time_ = hi;
  const Vec2 d = advance(dead_time_);
  model_advance_ = d.norm();
  direction_mismatch_ = wrapAngle(advance_angle - std::atan2(d.y(), d.x()));
}

DeadTimeModel DeadTimeModel::scaled(double factor) const {
  DeadTimeModel m;
  m.plus_ = plus_;
  m.minus_ = minus_;
  for (SignResponse* r : {&m.plus_, &m.minus_}) {
    r->yaw_rate *= factor;
    r->body_velocity[1] *= factor;
    r->speed = std::hypot(r->body_velocity[0], r->body_velocity[1]);
  }
  m.period_ = period_;
  m.drift_per_period_ = drift_per_period_;
  m.fit(advance_per_period_, advance_angle_);
  return m;
}

ModelMotion DeadTimeModel::segment(int sign, double heading, double dead, double duration) const {
  const SignResponse& r = sign > 0 ? plus_ : minus_;
  const double moving = std::max(0.0, duration - dead);
  ModelMotion m;
  const double turn = r.yaw_rate * moving;
  // The steady arc of the sign for `moving` seconds (holdDisplacement; straight for no turn).
  m.displacement = std::abs(turn) > 1e-9
                       ? holdDisplacement(r, heading, turn)
                       : Vec2(Eigen::Rotation2Dd(heading) *
                              Vec2(r.body_velocity[0], r.body_velocity[1]) * moving);
  m.turn = turn;
  m.dead_remaining = std::max(0.0, dead - duration);
  return m;
}

ModelMotion DeadTimeModel::until(double heading, int previous_sign, double dead_remaining,
                                 double plus_duration, double t, double dead_time) const {
  ModelMotion total;
  double dead = dead_remaining;
  int sign = previous_sign;
  double h = heading;
  const double pieces[2][2] = {{+1.0, std::min(t, plus_duration)},
                               {-1.0, std::max(0.0, t - plus_duration)}};
  for (const auto& piece : pieces) {
    const int s = static_cast<int>(piece[0]);
    if (piece[1] <= 0.0) continue;
    if (s != sign) dead = dead_time;  // a switch (or the start) begins a new dead time
    sign = s;
    const ModelMotion m = segment(s, h, dead, piece[1]);
    total.displacement += m.displacement;
    total.turn += m.turn;
    h += m.turn;
    dead = m.dead_remaining;
  }
  total.dead_remaining = dead;
  total.turn += drift_per_period_ * t / period_;
  return total;
}

ModelMotion DeadTimeModel::until(double heading, int previous_sign, double dead_remaining,
                                 double plus_duration, double t) const {
  return until(heading, previous_sign, dead_remaining, plus_duration, t, dead_time_);
}

}  // namespace flagella::control
