#include "flagella_sim/effects/granular_jamming.h"

#include <cmath>
#include <stdexcept>

#include "flagella_sim/core/geometry.h"

namespace flagella {

GranularJamming::GranularJamming() : Effect(kName, granularJammingEffect().parameters) {
  stiffness_ = parameterIndex("stiffness");
  release_force_ = parameterIndex("release_force");
  velocity_scale_ = parameterIndex("velocity_scale");
}

const EffectDescriptor& granularJammingEffect() {
  static const EffectDescriptor d = [] {
    EffectDescriptor e;
    e.name = GranularJamming::kName;
    e.description =
        "granular stick-slip: head resistance builds with distance pushed, then releases";
    e.parameters = {{"stiffness", 0.0, 0.0, 1e3, "N/m",
                     "jamming stiffness k_j: resistance gained per metre pushed"},
                    {"release_force", 1e-3, 1e-9, 10.0, "N",
                     "resistance F_r at which the jammed grains release"},
                    {"velocity_scale", 1e-6, 1e-9, 1e-2, "m/s",
                     "regularisation speed v_s of the resistance's sign function"}};
    e.make = [](const EffectBuildContext&) { return std::make_unique<GranularJamming>(); };
    DiscoveryHints h;
    h.title = "granular stick-slip (jamming and release)";
    h.signature = "intermittency: the head slows to a stop while resistance builds, then surges";
    h.needs = kTranslation | kTimeResolved;
    h.variables = {{"stiffness", "stiffness", false, "N/m", 1e-4, 1e3, true, 1e-4},
                   {"release_force", "release_force", false, "N", 1e-7, 1.0, true, 1e-7}};
    // A grid: the fit of a stick-slip is multimodal. Whether the head stops at a command depends
    // on F_r against the thrust there, so the training cost has a narrow valley in F_r: steps of
    // 10^0.1 (26 %) resolve commands whose thrusts differ by 1.3-2x. Release distances
    // s_r = F_r/k_j of 0.3, 1 and 3 mm.
    for (int i = 0; i <= 12; ++i) {
      const double release = 2.5e-4 * std::pow(10.0, 0.1 * i);  // 0.25-4 mN
      for (double distance : {3e-4, 1e-3, 3e-3}) h.starts.push_back({release / distance, release});
    }
    h.typical = {{"release_force", 1.5e-3, 3e-3, false}, {"stiffness", 0.8, 3.0, false}};
    h.steady_table_data = false;
    h.requires_effect = "rft";  // docs/model.md 2: the granular medium is RFT
    h.requires_what = "the granular medium's resistive force theory";
    e.discovery = h;
    return e;
  }();
  return d;
}

void GranularJamming::attach(const RodNetwork& net) {
  front_ = net.parts.head_front_node;
  node_ = net.parts.head_center_node;
}

double GranularJamming::resistance() const { return params_[stiffness_] * pushed_; }

void GranularJamming::setPushedDistance(double s) {
  if (!(s >= 0.0)) throw std::invalid_argument("granular_jamming: pushed distance must be >= 0");
  pushed_ = s;
}

void GranularJamming::setInternalState(const std::vector<double>& state) {
  setPushedDistance(state.at(0));
}

Vec3 GranularJamming::headAxis(const VecX& q) const {
  return (nodePosition(q, node_) - nodePosition(q, front_)).normalized();
}

void GranularJamming::addForce(const EffectContext& ctx, VecX& force,
                               JacobianSink* jacobian) const {
  const double resistance = this->resistance();
  if (resistance == 0.0) return;
  const Vec3 axis = headAxis(ctx.q_start);  // lagged with s
  const double v_axial = axis.dot(ctx.nodeVelocity(node_));
  const double v_s = params_[velocity_scale_];
  const double root = std::sqrt(v_axial * v_axial + v_s * v_s);
  // F = -(k_j s) a (a.v)/sqrt((a.v)^2 + v_s^2)
  force.segment<3>(3 * node_) -= (resistance * v_axial / root) * axis;
  if (!jacobian) return;
  // dF/dx_1 = (1/dt) dF/dv = -(k_j s/dt) a a^T v_s^2/((a.v)^2 + v_s^2)^(3/2)
  const double slope = resistance * v_s * v_s / (root * root * root);
  jacobian->addBlock(3 * node_, 3 * node_, (-slope / ctx.dt) * axis * axis.transpose());
}

void GranularJamming::acceptStep(const RodNetwork& /*net*/, const RodState& start,
                                 const RodState& end) {
  const Vec3 advance = nodePosition(end.q, node_) - nodePosition(start.q, node_);
  pushed_ += std::abs(headAxis(start.q).dot(advance));  // s += |a.dx_1|
  // The grains release where k_j s reaches F_r, at s_r = F_r/k_j inside the step; the distance
  // pushed past s_r loads the next jam, so s (and the run) depends continuously on F_r and k_j.
  // (F_r > 0, so a release implies k_j > 0)
  if (resistance() >= params_[release_force_])
    pushed_ = std::fmod(pushed_, params_[release_force_] / params_[stiffness_]);
}

}  // namespace flagella
