#include "flagella_sim/actuation/motor_load.h"

#include "flagella_sim/elastic/bend_twist_energy.h"
#include "flagella_sim/rod/rod_kinematics.h"

namespace flagella {

MotorLoad motorLoadAt(const RodNetwork& net, const RodState& state, double omega_cmd,
                      double time_next) {
  MotorLoad load;
  load.time = time_next;
  const int index = net.parts.motor_spring;
  if (index < 0) return load;
  // natural twist at t_k: the rest twist plus what the motor has turned (docs/model.md 1.9)
  const double tau_bar0 = net.bend_twist_springs[index].tau_bar;
  const BendTwistSpring spring = drivenSpring(net, {index, tau_bar0 + state.motor_twist_offset});
  const SpringEnergyTerms terms =
      bendTwistTerms(springGeometry(net, spring, state.q, state.frames, index), spring, false);
  const SpringDofMap map = springDofMap(net, spring);
  const int head_theta = net.thetaIndex(net.parts.head_edge);
  for (int a = 9; a < 11; ++a)  // the spring's local twist DOFs (docs/model.md 1.6)
    if (map.index[a] == head_theta) load.head_moment -= map.sign[a] * terms.gradient(a);
  load.torque = (omega_cmd >= 0.0 ? -1.0 : 1.0) * load.head_moment;  // along the command
  return load;
}

}  // namespace flagella
