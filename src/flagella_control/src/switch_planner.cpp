#include "flagella_control/switch_planner.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace flagella::control {
namespace {

constexpr double kShortestInterval = 1e-3;   // [s]; shorter pieces are dropped
constexpr double kMaxOffsetFraction = 0.45;  // |epsilon| <= this * T for steering by switching
constexpr double kParallelTolerance = 1e-6;  // |sin| of the angle between two sides

std::string describe(const Path& path, int element) {
  return "path element " + std::to_string(element) + " (" +
         (path.elements()[element].kind == PathElement::Kind::Line ? "line" : "arc") + ", " +
         std::to_string(path.elements()[element].length) + " m)";
}

class ScheduleBuilder {
 public:
  explicit ScheduleBuilder(SwitchSchedule& schedule) : schedule_(schedule) {}
  void add(int sign, double duration, int element) {
    if (duration < kShortestInterval) return;
    auto& iv = schedule_.intervals;
    if (!iv.empty() && iv.back().sign == sign) {
      iv.back().duration += duration;  // one switch fewer: merge equal signs
    } else {
      SwitchInterval s;
      s.start = schedule_.duration;
      s.duration = duration;
      s.sign = static_cast<std::int8_t>(sign);
      s.element = element;
      iv.push_back(s);
    }
    schedule_.duration += duration;
  }
  /// `periods` (possibly fractional) switching periods with halves T/2 +/- epsilon.
  void periods(const BinaryCalibration& c, double periods, double epsilon, int element) {
    const double plus = 0.5 * c.switch_period + epsilon, minus = 0.5 * c.switch_period - epsilon;
    const int whole = static_cast<int>(std::floor(periods));
    for (int k = 0; k < whole; ++k) {
      add(+1, plus, element);
      add(-1, minus, element);
    }
    const double fraction = periods - whole;
    add(+1, fraction * plus, element);
    add(-1, fraction * minus, element);
  }

 private:
  SwitchSchedule& schedule_;
};

}  // namespace

const SwitchInterval* SwitchSchedule::intervalAt(double t) const {
  if (intervals.empty() || t < 0.0 || t >= duration) return nullptr;
  auto it = std::upper_bound(intervals.begin(), intervals.end(), t,
                             [](double time, const SwitchInterval& s) { return time < s.start; });
  return &*(it - 1);
}

double halfPeriodOffset(const BinaryCalibration& c, double turn) {
  // Spec 7.3: a period of T/2 + eps at +omega and T/2 - eps at -omega turns by
  // drift + (omega_yr(+) - omega_yr(-)) eps.
  return (turn - c.heading_drift_per_period) / (c.plus.yaw_rate - c.minus.yaw_rate);
}

double periodStartHeading(const BinaryCalibration& c, double direction) {
  return wrapAngle(direction - c.advance_angle);
}

Vec2 holdDisplacement(const SignResponse& r, double heading, double turn) {
  // Integral of R(heading + w t) v_body dt until w t = turn:
  // (1/w) R(heading) [[sin a, -(1 - cos a)], [1 - cos a, sin a]] v_body.
  const double s = std::sin(turn), c = 1.0 - std::cos(turn);
  const Vec2 v(r.body_velocity[0], r.body_velocity[1]);
  const Vec2 local(s * v.x() - c * v.y(), c * v.x() + s * v.y());
  return Eigen::Rotation2Dd(heading) * local / r.yaw_rate;
}

namespace {

// Displacement while holding one sign for `duration` from `heading` (holdDisplacement by time;
// a series for a vanishing turn).
Vec2 holdFor(const SignResponse& r, double heading, double duration) {
  const double turn = r.yaw_rate * duration;
  if (std::abs(turn) > 1e-6) return holdDisplacement(r, heading, turn);
  return Eigen::Rotation2Dd(heading) * Vec2(r.body_velocity[0], r.body_velocity[1]) * duration;
}

PeriodMotion steadyPeriod(const BinaryCalibration& c, double heading, double plus_duration) {
  const double minus_duration = c.switch_period - plus_duration;
  PeriodMotion m;
  m.displacement = holdFor(c.plus, heading, plus_duration);
  const double mid = heading + c.plus.yaw_rate * plus_duration;
  m.displacement += holdFor(c.minus, mid, minus_duration);
  m.turn = c.plus.yaw_rate * plus_duration + c.minus.yaw_rate * minus_duration;
  return m;
}

}  // namespace

PeriodMotion predictPeriod(const BinaryCalibration& c, double heading, double plus_duration) {
  // Correction from the measured symmetric period (docs/model.md 7.3 "advance per period").
  const PeriodMotion ideal = steadyPeriod(c, 0.0, 0.5 * c.switch_period);
  const double scale = c.advance_per_period / ideal.displacement.norm();
  const double rotation =
      c.advance_angle - std::atan2(ideal.displacement.y(), ideal.displacement.x());
  PeriodMotion m = steadyPeriod(c, heading, plus_duration);
  m.displacement = Eigen::Rotation2Dd(rotation) * m.displacement * scale;
  // The steady responses already turn by (w+ + w-) T/2 over equal halves: add only what the
  // measured drift differs from that by (adding the whole drift counted it twice).
  m.turn += c.heading_drift_per_period - ideal.turn;
  return m;
}

SwitchSchedule planSchedule(const Path& path, const BinaryCalibration& c, int laps) {
  c.validate();
  if (path.empty()) throw std::invalid_argument("planner: the path is empty");
  if (laps < 1) throw std::invalid_argument("planner: laps must be >= 1");
  if (!path.closed()) laps = 1;
  const int n = static_cast<int>(path.elements().size());
  const int total = n * laps;
  const double advance = c.advance_per_period;

  // Corner after element k: which sign to hold, for how long, and how much of the sides before
  // (cut_before) and after (cut_after) the arc swept while turning replaces.
  struct Corner {
    int sign = 0;
    double hold = 0.0, cut_before = 0.0, cut_after = 0.0;
  };
  auto cornerAfter = [&](int k) {
    Corner corner;
    if (k == total - 1) return corner;  // the run ends here
    const int i = k % n;
    const double turn = path.turnAfter(i);
    if (std::abs(turn) < 1e-9) return corner;
    const SignResponse& r = (turn > 0) == (c.plus.yaw_rate > 0) ? c.plus : c.minus;
    corner.sign = &r == &c.plus ? +1 : -1;
    corner.hold = turn / r.yaw_rate;
    const PathElement& e = path.elements()[i];
    const double incoming = path.at(e.s_start + e.length - 1e-9).tangent;
    const double outgoing = incoming + turn;
    const Vec2 t1 = unitVector(incoming), t2 = unitVector(outgoing);
    const Vec2 d = holdDisplacement(r, periodStartHeading(c, incoming), turn);
    const double det = cross(t1, t2);
    if (std::abs(det) < kParallelTolerance) return corner;  // a U-turn: no cut is defined
    // Solve cut_before t1 + cut_after t2 = d: leave the side early, land on the next one.
    corner.cut_before = cross(d, t2) / det;
    corner.cut_after = cross(t1, d) / det;
    return corner;
  };

  SwitchSchedule schedule;
  ScheduleBuilder builder(schedule);
  double cut_at_start = 0.0;
  for (int k = 0; k < total; ++k) {
    const int i = k % n;
    const PathElement& e = path.elements()[i];
    const Corner corner = cornerAfter(k);
    const double length = e.length - cut_at_start - corner.cut_before;
    if (length < 0.0)
      throw std::invalid_argument(
          "planner: " + describe(path, i) +
          " is too short for the turns at its ends: " + "turning with this calibration uses " +
          std::to_string(cut_at_start + corner.cut_before) + " m of it");
    double turn_per_period = 0.0;
    if (e.kind == PathElement::Kind::Arc)
      turn_per_period = (e.sweep > 0 ? 1 : -1) * advance / e.radius;
    const double epsilon = halfPeriodOffset(c, turn_per_period);
    if (std::abs(epsilon) > kMaxOffsetFraction * c.switch_period)
      throw std::invalid_argument(
          "planner: " + describe(path, i) + " has radius " + std::to_string(e.radius) +
          " m, tighter than periodic switching can steer with this calibration (minimum about " +
          std::to_string(advance / (std::abs(c.plus.yaw_rate - c.minus.yaw_rate) *
                                    kMaxOffsetFraction * c.switch_period)) +
          " m)");
    builder.periods(c, length / advance, epsilon, i);
    builder.add(corner.sign, corner.hold, i);
    cut_at_start = corner.cut_after;
  }
  return schedule;
}

}  // namespace flagella::control
