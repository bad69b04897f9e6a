// Constant generalised forces on chosen DOFs (node forces in N, edge torques in N m): a tow
// force, a distributed load on a cantilever, a twisting moment. Zero Jacobian.
#pragma once

#include <utility>
#include <vector>

#include "flagella_sim/effects/effect.h"

namespace flagella {

class ConstantLoad : public Effect, public ForceLaw {
 public:
  static constexpr const char* kName = "constant_load";
  ConstantLoad() : Effect(kName) {}
  void addNodeForce(int node, const Vec3& f);
  void addEdgeTorque(const RodNetwork& net, int edge, double torque);
  void addForce(const EffectContext& ctx, VecX& force, JacobianSink* jacobian) const override;

 private:
  std::vector<std::pair<int, double>> loads_;
};

}  // namespace flagella
