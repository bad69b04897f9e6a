#include "flagella_sim/actuation/motor_command.h"

#include <algorithm>
#include <cmath>

#include "flagella_sim/core/parameter_set.h"

namespace flagella {

BinaryMotor::BinaryMotor(double omega, double positive_duration, double negative_duration,
                         double start_time)
    : omega_(omega),
      positive_(positive_duration),
      negative_(negative_duration),
      start_(start_time) {
  if (!(positive_duration > 0.0)) throw ConfigError("motor.positive_duration must be > 0 s");
  if (!(negative_duration > 0.0)) throw ConfigError("motor.negative_duration must be > 0 s");
}

double BinaryMotor::omega(double t) const {
  const double period = positive_ + negative_;
  double phase = std::fmod(t - start_, period);
  if (phase < 0.0) phase += period;
  return phase < positive_ ? omega_ : -omega_;
}

double RampedMotor::omega(double t) const {
  const double w = inner_->omega(t);
  if (ramp_ <= 0.0) return w;
  return w * std::clamp(t / ramp_, 0.0, 1.0);
}

}  // namespace flagella
