// The motor: one component of the simulation state. Commands go in (a schedule from the config
// or a controller, or set-points from outside through a validating gate with failsafe); the
// natural-twist rate of the motor spring comes out (docs/model.md 1.9), shaped by the torque-speed
// laws of effects such as dc_motor. The stepper integrates that rate into the motor's natural twist
// (RodState::motor_twist_offset); nothing else keeps a copy of the motor's state.
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "flagella_sim/actuation/command_gate.h"
#include "flagella_sim/actuation/motor_command.h"
#include "flagella_sim/effects/effect.h"

namespace flagella {

class Motor {
 public:
  explicit Motor(std::shared_ptr<const MotorCommand> schedule);

  // ---- commands in
  /// Replaces the schedule (controllers plug a CallbackMotor in here).
  void setSchedule(std::shared_ptr<const MotorCommand> schedule);
  const MotorCommand& schedule() const { return *schedule_; }
  /// From now on the motor follows set-points offered with command(), validated by a gate with
  /// failsafe; before the first valid one it follows the schedule if
  /// `schedule_until_first_command`, else it stands still.
  void takeCommands(const CommandGateOptions& gate, bool schedule_until_first_command);
  /// Offers a set-point [rad/s] at time `now` (commands mode only).
  CommandVerdict command(double omega, double now);
  /// The gate of commands mode (counters, rejections, failsafe), or nullptr.
  const CommandGate* gate() const { return gate_ ? &*gate_ : nullptr; }
  /// Forgets every command and the applied record (back to the state after construction).
  void clearCommands();
  /// While set, the set-point is 0 whatever the commands (a session's failure strategy).
  void setStopped(bool stopped) { stopped_ = stopped; }
  /// In commands mode, latches the set-point for the whole step starting at `time` (the gate's
  /// output then, or the schedule at time + dt before the first command).
  void beginStep(double time, double dt);

  // ---- speed out
  /// The torque-speed laws, chained in order (the effects in role MotorSpeedLaw).
  void setSpeedLaws(std::vector<const MotorSpeedLaw*> laws) { speed_laws_ = std::move(laws); }
  bool needsLoad() const { return !speed_laws_.empty(); }
  /// The command for the (sub)step ending at `t_next` [rad/s] (may be non-finite: the stepper
  /// reports that as a failure).
  double commandAt(double t_next) const;
  /// The natural-twist rate for a command under `load` (docs/model.md 1.9).
  double speed(double command, const MotorLoad& load) const;

  // ---- what was applied (the stepper records every accepted (sub)step)
  struct Record {
    double command = 0.0;  ///< omega_T of the last accepted (sub)step [rad/s]
    double speed = 0.0;    ///< natural-twist rate it applied [rad/s]
  };
  void recordApplied(double command, double speed) { record_ = {command, speed}; }
  const Record& record() const { return record_; }
  void restore(const Record& record) { record_ = record; }
  double lastCommand() const { return record_.command; }
  double lastSpeed() const { return record_.speed; }

 private:
  std::shared_ptr<const MotorCommand> schedule_;
  std::optional<CommandGate> gate_;
  bool schedule_until_first_command_ = true;
  bool stopped_ = false;
  double latched_ = 0.0;
  std::vector<const MotorSpeedLaw*> speed_laws_;
  Record record_;
};

}  // namespace flagella
