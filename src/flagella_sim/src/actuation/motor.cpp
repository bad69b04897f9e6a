#include "flagella_sim/actuation/motor.h"

#include <cmath>

#include "flagella_sim/actuation/motor_load.h"

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

MotorDrive Motor::drive(const RodNetwork& net, const RodState& state, double t_next,
                        double dt) const {
  MotorDrive d;
  d.command = commandAt(t_next);
  d.speed = d.command;
  if (!speed_laws_.empty() && std::isfinite(d.command)) {
    const MotorLoad load = motorLoadAt(net, state, d.command, t_next);
    for (const MotorSpeedLaw* law : speed_laws_) d.speed = law->motorSpeed(d.speed, load);
  }
  // docs/model.md 1.9: tau_bar(t_{k+1}) = tau_bar(t_k) + omega(t_{k+1}) dt (fully implicit)
  d.twist_offset = state.motor_twist_offset + d.speed * dt;
  return d;
}

void Motor::apply(const MotorDrive& drive, RodState& accepted) {
  accepted.motor_twist_offset = drive.twist_offset;
  record_ = {drive.command, drive.speed};
}

}  // namespace flagella
