#include "flagella_sim/effects/head_restraint.h"

namespace flagella {

HeadRestraint::HeadRestraint(double height_stiffness, double pitch_stiffness)
    : Effect(kName, headRestraintEffect().parameters) {
  height_k_ = parameterIndex("height_stiffness", height_stiffness);
  pitch_k_ = parameterIndex("pitch_stiffness", pitch_stiffness);
}

const EffectDescriptor& headRestraintEffect() {
  static const EffectDescriptor d = [] {
    EffectDescriptor e;
    e.name = HeadRestraint::kName;
    e.description = "soft springs on the head's height and pitch (a floating head)";
    e.parameters = {
        {"height_stiffness", 0.0, 0.0, 1e9, "N/m", "spring on the head centre's height"},
        {"pitch_stiffness", 0.0, 0.0, 1e9, "N m",
         "spring on the vertical component of the head axis"}};
    e.make = [](const EffectBuildContext&) { return std::make_unique<HeadRestraint>(0.0, 0.0); };
    return e;
  }();
  return d;
}

void HeadRestraint::attach(const RodNetwork& net) {
  front_ = net.parts.head_front_node;
  center_ = net.parts.head_center_node;
  rest_center_ = net.rest_positions[center_];
}

void HeadRestraint::addForce(const EffectContext& ctx, VecX& force, JacobianSink* jacobian) const {
  const Vec3& up = ctx.medium.up;
  const double k_h = params_[height_k_], k_p = params_[pitch_k_];
  const Vec3 x1 = nodePosition(ctx.q, center_);
  // Height: F_1 = -k_h ((x_1 - x_1(0)).up) up
  force.segment<3>(3 * center_) -= k_h * (x1 - rest_center_).dot(up) * up;
  // Pitch: s = t^0.up with t^0 = e/|e|, e = x_1 - x_0; ds/de = (up - s t)/|e|
  const Vec3 e = x1 - nodePosition(ctx.q, front_);
  const double len = e.norm();
  const Vec3 t = e / len;
  const double s = t.dot(up);
  const Vec3 g = (up - s * t) / len;
  force.segment<3>(3 * center_) -= k_p * s * g;
  force.segment<3>(3 * front_) += k_p * s * g;
  if (!jacobian) return;
  jacobian->addBlock(3 * center_, 3 * center_, -k_h * up * up.transpose());
  // d2s/de2 = -(t g^T + g t^T)/|e| - s (I - t t^T)/|e|^2
  const Mat3 hess_s = -(t * g.transpose() + g * t.transpose()) / len -
                      s * (Mat3::Identity() - t * t.transpose()) / (len * len);
  const Mat3 K = k_p * (g * g.transpose() + s * hess_s);
  jacobian->addBlock(3 * center_, 3 * center_, -K);
  jacobian->addBlock(3 * center_, 3 * front_, K);
  jacobian->addBlock(3 * front_, 3 * center_, K);
  jacobian->addBlock(3 * front_, 3 * front_, -K);
}

}  // namespace flagella
