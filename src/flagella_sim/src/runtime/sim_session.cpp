#include "flagella_sim/runtime/sim_session.h"

#include <cmath>

#include "flagella_sim/core/parameter_set.h"

namespace flagella {

namespace {
constexpr double kMaxMotorSpeed = 1e4;      // [rad/s], far above any soft robot's motor
constexpr double kMaxCommandTimeout = 1e6;  // [s]
constexpr double kMaxSliderTravel = 1.0;    // [m]

CommandGateOptions motorGateOptions(const SessionOptions& o) {
  CommandGateOptions g;
  g.field = "motor command omega";
  g.unit = "rad/s";
  g.min = -o.max_motor_speed;
  g.max = o.max_motor_speed;
  g.timeout = o.command_timeout;
  return g;
}

CommandGateOptions sliderGateOptions(const SessionOptions& o) {
  CommandGateOptions g;
  g.field = "slider command position";
  g.unit = "m";
  g.min = o.slider_min;
  g.max = o.slider_max;
  g.safe_value = std::min(std::max(0.0, o.slider_min), o.slider_max);
  return g;  // no failsafe: the mass stays where it was put
}

}  // namespace

void SessionOptions::validate() const {
  requireInRange("max_motor_speed", max_motor_speed, 1e-6, kMaxMotorSpeed, "rad/s");
  requireInRange("command_timeout", command_timeout, 0.0, kMaxCommandTimeout, "s (0: off)");
  if (initial_motor != "config" && initial_motor != "stopped")
    throw ConfigError("initial_motor must be \"config\" or \"stopped\", got \"" + initial_motor +
                      "\"");
  requireInRange("slider_min", slider_min, -kMaxSliderTravel, kMaxSliderTravel, "m");
  requireInRange("slider_max", slider_max, slider_min, kMaxSliderTravel, "m");
  imu.validate();
  accelerometer.validate();
  camera.validate();
}

SimSession::SimSession(SimulationConfig config, SessionOptions options)
    : config_(std::move(config)),
      options_((options.validate(), std::move(options))),
      slider_commands_(sliderGateOptions(options_)),
      imu_(options_.imu, config_.medium.gravity),
      accelerometer_(options_.accelerometer),
      camera_(options_.camera),
      output_from_sim_(outputFromSimulationFrame(config_.medium.up)) {
  start();
}

void SimSession::start() {
  sim_ = std::make_unique<Simulation>(config_);
  // Commands go to the simulation's motor; until the first one it follows the config's schedule
  // ("config") or stands still ("stopped").
  sim_->motor().takeCommands(motorGateOptions(options_), options_.initial_motor == "config");
  head_motion_.clear();
  const TrajectorySample s = sim_->sample();
  head_motion_.update(s.time, s.head_orientation, s.head_velocity);
  halted_ = false;
}

void SimSession::reset() {
  slider_commands_.clear();
  accelerometer_ = Accelerometer(options_.accelerometer);  // its clock starts again at t = 0
  steps_ = solver_failures_ = 0;
  last_failure_.clear();
  start();
}

CommandVerdict SimSession::commandMotor(double omega) {
  return sim_->motor().command(omega, time());
}

CommandVerdict SimSession::commandSlider(double position) {
  return slider_commands_.submit(position, time());
}

bool SimSession::step() {
  if (halted_) return false;
  slider_commands_.beginStep(sim_->slider(), time());
  try {
    sim_->step();
  } catch (const SolverFailure& first) {
    ++solver_failures_;
    last_failure_ = first.what();
    Motor& motor = sim_->motor();
    motor.setStopped(true);
    try {
      sim_->step();
      motor.setStopped(false);
    } catch (const SolverFailure& second) {
      motor.setStopped(false);
      last_failure_ = std::string(second.what()) + " (also with the motor stopped: halted)";
      halted_ = true;
      return false;
    }
  }
  ++steps_;
  const TrajectorySample s = sim_->sample();
  head_motion_.update(s.time, s.head_orientation, s.head_velocity);
  return true;
}

RodSnapshot SimSession::snapshot() const { return takeSnapshot(*sim_, output_from_sim_); }

ImuSample SimSession::measureImu() {
  ImuSample sample = imu_.measure(head_motion_.motion());
  sample.orientation = (output_from_sim_ * sample.orientation).normalized();
  if (options_.accelerometer.feeds_imu) {
    const AccelerometerOptions& a = options_.accelerometer;
    sample.linear_acceleration = measureAccelerometer().acceleration;
    // white noise plus the quantization's uniform error (one count wide)
    sample.linear_acceleration_variance =
        a.noise_std * a.noise_std + a.resolution * a.resolution / 12.0;
  }
  return sample;
}

const AccelerometerReading& SimSession::measureAccelerometer() {
  accelerometer_.update(time(), specificForceInHead(head_motion_.motion(), config_.medium.gravity));
  return accelerometer_.reading();
}

CameraFix SimSession::measureCamera() {
  return camera_.measure(time(), output_from_sim_ * sim_->sample().head_position);
}

bool SimSession::failsafeActive() const { return sim_->motor().gate()->failsafeTripped(time()); }

SessionHealth SimSession::health() const {
  SessionHealth h;
  const TrajectorySample s = sim_->sample();
  h.steps = steps_;
  h.newton_iterations = s.newton_iterations;
  h.subdivided_steps = s.subdivided_steps;
  h.damped_steps = s.damped_steps;
  h.solver_failures = solver_failures_;
  const CommandGate& motor_gate = *sim_->motor().gate();
  h.motor_accepted = motor_gate.acceptedCount();
  h.motor_rejected = motor_gate.rejectedCount();
  const CommandGate& slider_gate = slider_commands_.gate();
  h.slider_accepted = slider_gate.acceptedCount();
  h.slider_rejected = slider_gate.rejectedCount();
  h.failsafe_active = motor_gate.failsafeTripped(time());
  h.halted = halted_;
  h.motor_applied = sim_->lastMotorCommand();
  if (const Slider* slider = sim_->slider()) {
    h.slider_position = slider->state().position;
    h.slider_at_stop = slider->state().at_stop;
  } else {
    h.slider_position = slider_commands_.setPoint(time());
  }
  h.last_rejection =
      motor_gate.lastRejection().empty() ? slider_gate.lastRejection() : motor_gate.lastRejection();
  h.last_solver_failure = last_failure_;
  if (halted_) {
    h.level = HealthLevel::Error;
    h.message = "halted after a solver failure: " + last_failure_ + "; call reset";
  } else if (solver_failures_ > 0) {
    h.level = HealthLevel::Warn;
    h.message = std::to_string(solver_failures_) +
                " step(s) failed and were retried with the motor stopped; last: " + last_failure_;
  } else if (h.failsafe_active) {
    h.level = HealthLevel::Warn;
    h.message = "command timeout: motor stopped by the failsafe";
  }
  return h;
}

}  // namespace flagella
