#include "flagella_sim/effects/com_offset.h"

#include <cmath>

namespace flagella {

ComOffset::ComOffset(double head_mass) : Effect(kName) {
  offset_ =
      params_.declare("offset", 0.0, -0.1, 0.1, "m",
                      "axial COM - buoyancy offset l, positive along +t^0 (toward the tails)");
  head_mass_ = params_.declare("head_mass", head_mass, kMinHeadMass, kMaxHeadMass, "kg",
                               "head mass m_h (default rho_m pi a^2 L_head)");
}

void ComOffset::attach(const RodNetwork& net) {
  front_ = net.parts.head_front_node;
  joint_ = net.parts.joint_node;
  separation_ = (net.rest_positions[joint_] - net.rest_positions[front_]).norm();
}

void ComOffset::addForce(const EffectContext& ctx, VecX& force, JacobianSink* /*jacobian*/) const {
  const double l = params_[offset_];
  const double added_mass = params_[head_mass_] * std::abs(l) / separation_;  // M_a = m_h |l|/d
  const int com_side = l >= 0.0 ? joint_ : front_;
  const int other = l >= 0.0 ? front_ : joint_;
  force.segment<3>(3 * com_side) += added_mass * ctx.medium.gravity;  // +M_a g on the COM side
  force.segment<3>(3 * other) -= added_mass * ctx.medium.gravity;     // -M_a g on the other
}

}  // namespace flagella
