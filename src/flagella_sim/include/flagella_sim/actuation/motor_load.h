// The motor's load (docs/model.md 1.9): the motor spring's moment on the head, read from the
// spring's bending-twisting terms with the natural twist the motor has reached.
#pragma once

#include "flagella_sim/effects/effect.h"
#include "flagella_sim/rod/rod_network.h"
#include "flagella_sim/rod/rod_state.h"

namespace flagella {

/// The load at `state` (the start of a step, so the speed of the step does not depend on the
/// unknown end state) for a command `omega_cmd`, for the (sub)step ending at `time_next`: the
/// motor spring's generalised force on theta^0 with the natural twist tau_bar(0) +
/// state.motor_twist_offset. A network without a motor spring has no load.
MotorLoad motorLoadAt(const RodNetwork& net, const RodState& state, double omega_cmd,
                      double time_next);

}  // namespace flagella
