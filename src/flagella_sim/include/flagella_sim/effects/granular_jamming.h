// Stick-slip of the head in jammed grains (model extension for identification): a yield force
// that grows with the distance s the head has been pushed since the last release,
// F = -(k_j s) v/sqrt(|v|^2 + v_s^2) on x_1, and drops to zero (s = 0) once k_j s >= F_r.
// s is lagged (its value at the start of the step), so the Jacobian is granular_yield's with
// F_y = k_j s; it is updated after every accepted (sub)step: s += |x_1(t_{k+1}) - x_1(t_k)|.
#pragma once

#include "flagella_sim/effects/effect.h"

namespace flagella {

class GranularJamming : public Effect {
 public:
  static constexpr const char* kName = "granular_jamming";
  GranularJamming();
  void attach(const RodNetwork& net) override;
  void addForce(const EffectContext& ctx, VecX& force, JacobianSink* jacobian) const override;
  void acceptStep(const RodNetwork& net, const RodState& start, const RodState& end) override;
  std::vector<double> internalState() const override { return {pushed_}; }
  void setInternalState(const std::vector<double>& state) override;

  /// s: distance the head has been pushed since the last release [m].
  double pushedDistance() const { return pushed_; }
  void setPushedDistance(double s);
  /// Current resistance k_j s [N] (the yield force of the next step).
  double resistance() const;

 private:
  int stiffness_ = 0, release_force_ = 0, velocity_scale_ = 0;
  int node_ = 1;
  double pushed_ = 0.0;
};

}  // namespace flagella
