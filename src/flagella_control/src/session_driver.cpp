#include "flagella_control/session_driver.h"

#include <algorithm>
#include <stdexcept>

#include "flagella_control/validation.h"

namespace flagella::control {

namespace {
flagella::SessionOptions sessionOptions(const flagella::SimulationConfig& config, double omega) {
  flagella::SessionOptions o;
  o.initial_motor = "stopped";
  o.command_timeout = 0.0;  // no failsafe: every step is commanded anyway
  o.max_motor_speed = std::max(o.max_motor_speed, 1.01 * omega);
  if (config.slider.enabled) {  // the gate admits the whole travel
    o.slider_min = config.slider.travel_min;
    o.slider_max = config.slider.travel_max;
  }
  return o;
}
}  // namespace

SessionDriver::SessionDriver(const flagella::SimulationConfig& config, double max_omega,
                             std::string run)
    : session_(config, sessionOptions(config, max_omega)),
      ramp_(config.motor.ramp_time),
      run_(std::move(run)) {}

double SessionDriver::step(double signed_omega) {
  const double t_end = session_.time() + session_.dt();
  const double scale = ramp_ > 0.0 ? std::min(1.0, t_end / ramp_) : 1.0;
  const double applied = signed_omega * scale;
  const flagella::CommandVerdict verdict = session_.commandMotor(applied);
  if (verdict != flagella::CommandVerdict::Accepted)
    throw std::runtime_error("calibration " + run_ +
                             ": motor command rejected: " + session_.health().last_rejection);
  const bool ok = session_.step();
  const flagella::SessionHealth h = session_.health();
  if (!ok || h.solver_failures > 0)
    throw std::runtime_error("calibration " + run_ + ": solver failure at t = " +
                             numberString(session_.time()) + " s (" + h.message + ")");
  return applied;
}

void SessionDriver::commandSlider(double position) {
  if (session_.commandSlider(position) != flagella::CommandVerdict::Accepted)
    throw std::runtime_error("calibration " + run_ +
                             ": slider command rejected: " + session_.health().last_rejection);
}

}  // namespace flagella::control
