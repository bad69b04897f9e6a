#include <cmath>
#include <stdexcept>
#include <string>

#include "flagella_control/controller_core.h"

namespace flagella::control {

PeriodicSwitchController::PeriodicSwitchController(double omega, double positive_duration,
                                                   double negative_duration)
    : omega_(omega), positive_(positive_duration), negative_(negative_duration) {
  if (!(omega > 0.0) || !std::isfinite(omega))
    throw std::invalid_argument("periodic switch: omega must be > 0 and finite, got " +
                                std::to_string(omega));
  if (!(positive_duration > 0.0) || !(negative_duration > 0.0) ||
      !std::isfinite(positive_duration + negative_duration))
    throw std::invalid_argument("periodic switch: both half-period durations must be > 0");
}

ControllerOutputs PeriodicSwitchController::step(const ControllerInputs& in) {
  if (!started_) {
    started_ = true;
    start_time_ = in.time;
  }
  // Phase within the period (docs/model.md 7.3): first the positive half, then the negative one.
  const double period = positive_ + negative_;
  const double phase = std::fmod(std::max(0.0, in.time - start_time_), period);
  ControllerOutputs out;
  out.motor_command = phase < positive_ ? omega_ : -omega_;
  out.mode = ControllerMode::Running;
  return out;
}

}  // namespace flagella::control
