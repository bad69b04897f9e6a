// Slider set-points from outside (a controller, the slider_command topic): validated by a gate
// without failsafe (the mass stays where it was put), and latched into the slider's target at the
// start of each step, as the motor latches its own (Motor::takeCommands). A config without a
// slider has the accepted set-point stored and reported only.
#pragma once

#include <utility>

#include "flagella_sim/actuation/command_gate.h"
#include "flagella_sim/actuation/slider.h"

namespace flagella {

class SliderCommands {
 public:
  explicit SliderCommands(CommandGateOptions gate) : gate_(std::move(gate)) {}

  /// Offers a position [m] at time `now`; a rejected one leaves the set-point as it was.
  CommandVerdict submit(double position, double now) { return gate_.submit(position, now); }
  /// At the start of the step from `now`: the accepted set-point becomes the slider's target
  /// (nothing before the first accepted command, or without a slider).
  void beginStep(Slider* slider, double now) const {
    if (slider && gate_.hasCommand()) slider->setTarget(gate_.output(now));
  }
  /// The set-point at `now` (the gate's safe value before the first command).
  double setPoint(double now) const { return gate_.output(now); }
  const CommandGate& gate() const { return gate_; }
  /// Forgets every command.
  void clear() { gate_.clear(); }

 private:
  CommandGate gate_;
};

}  // namespace flagella
