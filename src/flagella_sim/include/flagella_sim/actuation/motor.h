// The motor: one component of the simulation state. Commands go in (a schedule from the config
// or a controller, or set-points from outside through a validating gate with failsafe); the
// natural-twist rate of the motor spring comes out (docs/model.md 1.9), shaped by the torque-speed
// laws of effects such as dc_motor, and its integral, the motor's natural twist, which the state
// carries (RodState::motor_twist_offset) and only the motor writes. Nothing else keeps a copy of
// the motor's state.
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "flagella_sim/actuation/command_gate.h"
#include "flagella_sim/actuation/motor_command.h"
#include "flagella_sim/effects/effect.h"
#include "flagella_sim/rod/rod_network.h"
#include "flagella_sim/rod/rod_state.h"

namespace flagella {

/// What the motor drives over one (sub)step.
struct MotorDrive {
  double command = 0.0;       ///< the command [rad/s] (may be non-finite: see Motor::drive)
  double speed = 0.0;         ///< natural-twist rate after the torque-speed laws [rad/s]
  double twist_offset = 0.0;  ///< tau_bar(t_{k+1}) - tau_bar(0) of the motor spring [rad]
};

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

  // ---- speed and natural twist out
  /// The torque-speed laws, chained in order (the effects in role MotorSpeedLaw).
  void setSpeedLaws(std::vector<const MotorSpeedLaw*> laws) { speed_laws_ = std::move(laws); }
  /// The drive of the (sub)step of length `dt` from `state` to `t_next`: the command, the speed
  /// under the load at `state`, and the natural twist it reaches. A non-finite command or speed
  /// comes back as it is (the stepper reports it as a failure of the step).
  MotorDrive drive(const RodNetwork& net, const RodState& state, double t_next, double dt) const;
  /// An accepted (sub)step: `accepted` carries the drive's natural twist, and the record keeps
  /// what was applied.
  void apply(const MotorDrive& drive, RodState& accepted);

  // ---- what was applied (recorded for every accepted (sub)step)
  struct Record {
    double command = 0.0;  ///< omega_T of the last accepted (sub)step [rad/s]
    double speed = 0.0;    ///< natural-twist rate it applied [rad/s]
  };
  const Record& record() const { return record_; }
  void restore(const Record& record) { record_ = record; }
  double lastCommand() const { return record_.command; }
  double lastSpeed() const { return record_.speed; }

 private:
  /// The command for the (sub)step ending at `t_next` [rad/s].
  double commandAt(double t_next) const;

  std::shared_ptr<const MotorCommand> schedule_;
  std::optional<CommandGate> gate_;
  bool schedule_until_first_command_ = true;
  bool stopped_ = false;
  double latched_ = 0.0;
  std::vector<const MotorSpeedLaw*> speed_laws_;
  Record record_;
};

}  // namespace flagella
