#include "flagella_sim/effects/com_offset.h"

#include <cmath>

namespace flagella {

ComOffset::ComOffset(double head_mass) : Effect(kName, comOffsetEffect().parameters) {
  offset_ = parameterIndex("offset");
  head_mass_ = parameterIndex("head_mass", head_mass);
}

namespace {
// m_h = rho_m pi a^2 L_head (docs/model.md 5) unless the config gives it (then any in-range value
// serves until the configured one is set).
double defaultHeadMass(const EffectBuildContext& b) {
  if (b.spec.hasParameter("head_mass")) return ComOffset::kMinHeadMass;
  const double a = b.robot.head_radius;
  const double m = b.medium.density() * M_PI * a * a * b.robot.head_length;  // docs/model.md 5
  if (!(m >= ComOffset::kMinHeadMass && m <= ComOffset::kMaxHeadMass))
    throw ConfigError(rangeMessage("effects.com_offset.head_mass (default rho_m pi a^2 L_head)", m,
                                   ComOffset::kMinHeadMass, ComOffset::kMaxHeadMass, "kg") +
                      "; give effects.com_offset.head_mass");
  return m;
}
}  // namespace

const EffectDescriptor& comOffsetEffect() {
  static const EffectDescriptor d = [] {
    EffectDescriptor e;
    e.name = ComOffset::kName;
    e.description = "gravity couple from an axial offset of the head's centre of mass";
    e.parameters = {{"offset", 0.0, -0.1, 0.1, "m",
                     "axial COM - buoyancy offset l, positive along +t^0 (toward the tails)"},
                    {"head_mass", 0.05, ComOffset::kMinHeadMass, ComOffset::kMaxHeadMass, "kg",
                     "head mass m_h (default rho_m pi a^2 L_head)"}};
    e.default_rules = {{"head_mass", "medium.density pi robot.head_radius^2 robot.head_length"}};
    e.make = [](const EffectBuildContext& c) {
      return std::make_unique<ComOffset>(defaultHeadMass(c));
    };
    DiscoveryHints h;
    h.title = "centre-of-mass offset with gravity and buoyancy";
    h.signature = "drift in pitch: the head axis tilts and the path climbs or dives";
    h.needs = kVertical | kTimeResolved;
    h.variables = {{"offset", "offset", false, "m", -0.05, 0.05, false, 0.0}};
    h.starts = {{-2e-3}, {2e-3}};
    h.typical = {{"offset", 1e-3, 4e-3, true}};
    // the helical robot's whole body pitches under the head's weight: 1.2 mm turns it upright
    // within 40 s, 0.03-0.1 mm (a fabrication tolerance) tilts its track by a few degrees
    h.typical_single_flagellum = {{"offset", 3e-5, 1e-4, true}};
    h.steady_table_data = false;
    e.discovery = h;
    return e;
  }();
  return d;
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
