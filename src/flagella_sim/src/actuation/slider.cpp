#include "flagella_sim/actuation/slider.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "flagella_sim/core/parameter_set.h"
#include "flagella_sim/core/units.h"

namespace flagella {

namespace {
constexpr double kMaxSubStep = 1e-3;  // [s]
}

double SliderSpec::maxSpeed() const { return lead * max_screw_rate / (2.0 * units::pi); }

double SliderSpec::maxAcceleration() const { return lead * max_screw_accel / (2.0 * units::pi); }

void SliderSpec::validate() const {
  using namespace slider_limits;
  requireInRange("slider.mass", mass, kMinMass, kMaxMass, "kg");
  requireInRange("slider.lead", lead, kMinLead, kMaxLead, "m");
  requireInRange("slider.max_screw_rate", max_screw_rate, kMinScrewRate, kMaxScrewRate, "rad/s");
  requireInRange("slider.max_screw_accel", max_screw_accel, kMinScrewAccel, kMaxScrewAccel,
                 "rad/s^2");
  requireInRange("slider.travel_min", travel_min, -kMaxTravel, 0.0, "m");
  requireInRange("slider.travel_max", travel_max, 0.0, kMaxTravel, "m");
  if (!(travel_max > travel_min))
    throw ConfigError("slider.travel_max must be > slider.travel_min");
  requireInRange("slider.initial_position", initial_position, travel_min, travel_max, "m");
}

Slider::Slider(const SliderSpec& spec) : spec_(spec) {
  spec_.validate();
  state_.position = state_.target = spec_.initial_position;
}

void Slider::setTarget(double target) {
  if (!std::isfinite(target))
    throw std::invalid_argument("slider target must be finite, got " + std::to_string(target));
  state_.target = target;
}

double Slider::comOffset(double neutral_offset, double head_mass) const {
  return neutral_offset + spec_.mass / head_mass * state_.position;  // docs/model.md 5
}

double Slider::screwRate() const { return 2.0 * units::pi * state_.velocity / spec_.lead; }

void Slider::advance(double dt) {
  const int pieces = std::max(1, static_cast<int>(std::ceil(dt / kMaxSubStep - 1e-9)));
  for (int i = 0; i < pieces; ++i) subStep(dt / pieces);
}

void Slider::subStep(double h) {
  const double a_max = spec_.maxAcceleration(), v_max = spec_.maxSpeed();
  SliderState& s = state_;
  const double goal = std::clamp(s.target, spec_.travel_min, spec_.travel_max);
  const double error = goal - s.position;
  if (std::abs(error) <= 0.5 * a_max * h * h && std::abs(s.velocity) <= a_max * h) {
    s.position = goal;  // within one sub-step's reach at rest: arrive
    s.velocity = 0.0;
  } else {
    // Trapezoidal move: the speed after this sub-step may be at most v_max and at most what
    // still stops on the target at a_max, v'^2/(2 a) <= e - (v + v') h/2 (the braking curve
    // v = sqrt(2 a e), kept exactly with the trapezoid rule); it changes by at most a_max h.
    const double direction = error > 0.0 ? 1.0 : -1.0;
    const double ahead = std::abs(error) - 0.5 * direction * s.velocity * h;
    const double braking =
        ahead > 0.0
            ? -0.5 * a_max * h + std::sqrt(0.25 * a_max * a_max * h * h + 2.0 * a_max * ahead)
            : 0.0;
    const double allowed = direction * std::min(v_max, braking);
    const double v_new = s.velocity + std::clamp(allowed - s.velocity, -a_max * h, a_max * h);
    s.position += 0.5 * (s.velocity + v_new) * h;
    s.velocity = v_new;
  }
  // Hard stops: never passed; resting against one is reported (and counted once per arrival).
  const bool was_at_stop = s.at_stop;
  s.position = std::clamp(s.position, spec_.travel_min, spec_.travel_max);
  s.at_stop = s.position == spec_.travel_min || s.position == spec_.travel_max;
  if (s.at_stop) s.velocity = 0.0;  // arrived (already at rest) or stopped by the clamp
  if (s.at_stop && !was_at_stop) ++s.stop_hits;
}

}  // namespace flagella
