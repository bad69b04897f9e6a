// Sources of the motor speed omega_T(t) that drives the natural twist of the motor spring
// (docs/model.md 1.9). Controllers plug in through CallbackMotor.
#pragma once

#include <functional>
#include <memory>

namespace flagella {

class MotorCommand {
 public:
  virtual ~MotorCommand() = default;
  /// Motor speed omega_T at time t [rad/s], positive about t^1.
  virtual double omega(double t) const = 0;
};

class ConstantMotor : public MotorCommand {
 public:
  explicit ConstantMotor(double omega) : omega_(omega) {}
  double omega(double /*t*/) const override { return omega_; }

 private:
  double omega_;
};

/// Binary +/-omega schedule (docs/model.md 7.3): +omega for `positive_duration`, then -omega for
/// `negative_duration`, repeating from `start_time`. Unequal durations steer large circles.
class BinaryMotor : public MotorCommand {
 public:
  BinaryMotor(double omega, double positive_duration, double negative_duration,
              double start_time = 0.0);
  double omega(double t) const override;

 private:
  double omega_, positive_, negative_, start_;
};

/// Any function of time: the hook where controllers drive the motor.
class CallbackMotor : public MotorCommand {
 public:
  explicit CallbackMotor(std::function<double(double)> fn) : fn_(std::move(fn)) {}
  double omega(double t) const override { return fn_(t); }

 private:
  std::function<double(double)> fn_;
};

/// Scales another command by min(1, t / ramp_time): a soft start that avoids an impulsive
/// load on the first step.
class RampedMotor : public MotorCommand {
 public:
  RampedMotor(std::shared_ptr<const MotorCommand> inner, double ramp_time)
      : inner_(std::move(inner)), ramp_(ramp_time) {}
  double omega(double t) const override;

 private:
  std::shared_ptr<const MotorCommand> inner_;
  double ramp_;
};

}  // namespace flagella
