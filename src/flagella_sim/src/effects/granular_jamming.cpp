#include "flagella_sim/effects/granular_jamming.h"

#include <stdexcept>

#include "flagella_sim/effects/granular_yield.h"

namespace flagella {

GranularJamming::GranularJamming() : Effect(kName) {
  stiffness_ = params_.declare("stiffness", 0.0, 0.0, 1e3, "N/m",
                               "jamming stiffness k_j: resistance gained per metre pushed");
  release_force_ = params_.declare("release_force", 1e-3, 1e-9, 10.0, "N",
                                   "resistance F_r at which the jammed grains release");
  velocity_scale_ = params_.declare("velocity_scale", 1e-6, 1e-9, 1e-2, "m/s",
                                    "regularisation speed v_s of the yield force's sign function");
}

void GranularJamming::attach(const RodNetwork& net) { node_ = net.parts.head_center_node; }

double GranularJamming::resistance() const { return params_[stiffness_] * pushed_; }

void GranularJamming::setPushedDistance(double s) {
  if (!(s >= 0.0)) throw std::invalid_argument("granular_jamming: pushed distance must be >= 0");
  pushed_ = s;
}

void GranularJamming::setInternalState(const std::vector<double>& state) {
  setPushedDistance(state.at(0));
}

void GranularJamming::addForce(const EffectContext& ctx, VecX& force,
                               JacobianSink* jacobian) const {
  // F = -(k_j s) v / sqrt(|v|^2 + v_s^2), s lagged
  addRegularizedCoulombForce(ctx, node_, resistance(), params_[velocity_scale_], force, jacobian);
}

void GranularJamming::acceptStep(const RodNetwork& /*net*/, const RodState& start,
                                 const RodState& end) {
  pushed_ += (nodePosition(end.q, node_) - nodePosition(start.q, node_)).norm();  // s += |dx_1|
  if (resistance() >= params_[release_force_]) pushed_ = 0.0;  // k_j s >= F_r: grains release
}

}  // namespace flagella
