#include "flagella_sim/effects/constant_load.h"

namespace flagella {

void ConstantLoad::addNodeForce(int node, const Vec3& f) {
  for (int a = 0; a < 3; ++a) loads_.emplace_back(3 * node + a, f(a));
}

void ConstantLoad::addEdgeTorque(const RodNetwork& net, int edge, double torque) {
  loads_.emplace_back(net.thetaIndex(edge), torque);
}

void ConstantLoad::addForce(const EffectContext& /*ctx*/, VecX& force,
                            JacobianSink* /*jac*/) const {
  for (const auto& [dof, value] : loads_) force(dof) += value;
}

}  // namespace flagella
