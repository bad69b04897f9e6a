#include "flagella_sim/actuation/motor.h"

namespace flagella {

Motor::Motor(std::shared_ptr<const MotorCommand> schedule) : schedule_(std::move(schedule)) {}

void Motor::setSchedule(std::shared_ptr<const MotorCommand> schedule) {
  schedule_ = std::move(schedule);
}

void Motor::takeCommands(const CommandGateOptions& gate, bool schedule_until_first_command) {
  gate_.emplace(gate);
  schedule_until_first_command_ = schedule_until_first_command;
}

CommandVerdict Motor::command(double omega, double now) {
  if (!gate_) throw std::logic_error("Motor::command: call takeCommands first");
  return gate_->submit(omega, now);
}

void Motor::clearCommands() {
  if (gate_) gate_->clear();
  stopped_ = false;
  latched_ = 0.0;
  record_ = Record{};
}

void Motor::beginStep(double time, double dt) {
  if (!gate_) return;
  if (!gate_->hasCommand() && schedule_until_first_command_)
    latched_ = schedule_->omega(time + dt);
  else
    latched_ = gate_->output(time);
}

double Motor::commandAt(double t_next) const {
  if (stopped_) return 0.0;
  return gate_ ? latched_ : schedule_->omega(t_next);
}

double Motor::speed(double command, const MotorLoad& load) const {
  double omega = command;
  for (const MotorSpeedLaw* law : speed_laws_) omega = law->motorSpeed(omega, load);
  return omega;
}

}  // namespace flagella
