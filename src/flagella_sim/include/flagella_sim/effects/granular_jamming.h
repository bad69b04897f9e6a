// Stick-slip of the head in jammed grains (model extension for identification): a resistance to
// the head's advance along its own axis that grows with the distance s the head has pushed
// since the last release, F = -(k_j s) a (a.v)/sqrt((a.v)^2 + v_s^2) on x_1, and drops to zero
// where k_j s reaches F_r (s = s_r = F_r/k_j; the distance pushed past s_r within the step carries
// over: s = s mod s_r). Only the axial motion loads the grains ahead of the head: the
// sideways wobble of a spinning head neither builds nor meets this resistance.
// The axis a = (x_1 - x_0)/|x_1 - x_0| and s are lagged (their values at the start of the
// step), so dF/dx_1 = -(k_j s/dt) a a^T v_s^2/((a.v)^2 + v_s^2)^(3/2); after every accepted
// (sub)step s += |a.(x_1(t_{k+1}) - x_1(t_k))|.
#pragma once

#include "flagella_sim/effects/effect.h"
#include "flagella_sim/effects/effect_descriptor.h"

namespace flagella {

/// The registry entry (effect_list.def).
const EffectDescriptor& granularJammingEffect();

class GranularJamming : public Effect, public ForceLaw, public StepHooks {
 public:
  static constexpr const char* kName = "granular_jamming";
  GranularJamming();
  void attach(const RodNetwork& net) override;
  void addForce(const EffectContext& ctx, VecX& force, JacobianSink* jacobian) const override;
  void acceptStep(const RodNetwork& net, const RodState& start, const RodState& end) override;
  std::vector<double> internalState() const override { return {pushed_}; }
  void setInternalState(const std::vector<double>& state) override;

  /// s: distance the head has pushed along its axis since the last release [m].
  double pushedDistance() const { return pushed_; }
  void setPushedDistance(double s);
  /// Current resistance k_j s [N] (the yield force of the next step).
  double resistance() const;

 private:
  /// Unit head axis x_1 - x_0 at the configuration q.
  Vec3 headAxis(const VecX& q) const;

  int stiffness_ = 0, release_force_ = 0, velocity_scale_ = 0;
  int front_ = 0, node_ = 1;
  double pushed_ = 0.0;
};

}  // namespace flagella
