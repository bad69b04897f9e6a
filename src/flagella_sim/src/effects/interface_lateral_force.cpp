#include "flagella_sim/effects/interface_lateral_force.h"

#include <cmath>

#include "flagella_sim/core/geometry.h"

namespace flagella {

namespace {
// The integrand is smooth and periodic, so the trapezoid rule converges spectrally.
constexpr int kQuadraturePoints = 4096;
}  // namespace

double integratedLateralCoefficient(double onset_over_radius, double sharpness) {
  double sum = 0.0;
  for (int i = 0; i < kQuadraturePoints; ++i) {
    const double phi = 2.0 * M_PI * i / kQuadraturePoints;
    const double y = std::sin(phi);  // height over R of the surface point (docs/model.md 3.3)
    sum += std::sin(phi) / (1.0 + std::exp(sharpness * (y - onset_over_radius)));
  }
  return -sum * 2.0 * M_PI / kQuadraturePoints;
}

InterfaceLateralForce::InterfaceLateralForce(double C_yr, double head_radius, double head_length)
    : Effect(kName, interfaceLateralForceEffect().parameters) {
  c_yr_ = parameterIndex("C_yr", C_yr);
  radius_ = parameterIndex("head_radius", head_radius);
  length_ = parameterIndex("head_length", head_length);
}

namespace {
EffectPtr makeInterfaceLateralForce(const EffectBuildContext& b) {
  double c_yr = 0.0;
  if (b.spec.option("mode") == "integrated") {
    if (b.spec.hasParameter("C_yr"))
      throw ConfigError(
          "effects.interface_lateral_force.C_yr is computed in mode 'integrated'; remove it or use "
          "mode 'fitted'");
    // docs/model.md 3.3: C_yr from the viscosity profile integral I(h/R, k)
    const InterfaceViscosityProfile& p = b.medium.profile;
    c_yr = integratedLateralCoefficient(p.onset_height / p.length_scale, p.sharpness);
  }
  return std::make_unique<InterfaceLateralForce>(c_yr, b.robot.head_radius, b.robot.head_length);
}
}  // namespace

const EffectDescriptor& interfaceLateralForceEffect() {
  static const EffectDescriptor d = [] {
    EffectDescriptor e;
    e.name = InterfaceLateralForce::kName;
    e.description = "lateral force on a head spinning at an air-liquid interface";
    e.options = {{"mode",
                  "fitted",
                  {"fitted", "integrated"},
                  "C_yr given (fitted) or from the viscosity profile (integrated)"}};
    e.parameters = {{"C_yr", 0.0, -1e4, 1e4, "", "lateral rotation-induced force coefficient"},
                    {"head_radius", 0.02, 1e-6, 10.0, "m", "head radius R"},
                    {"head_length", 0.04, 1e-6, 10.0, "m", "head length L_head"}};
    e.default_rules = {{"C_yr", "0 (mode fitted), the profile integral (mode integrated)"},
                       {"head_radius", "robot.head_radius"},
                       {"head_length", "robot.head_length"}};
    e.make = makeInterfaceLateralForce;
    DiscoveryHints h;
    h.title = "depth-dependent viscosity near an interface (lateral head force)";
    h.signature = "circling: a steady yaw rate that reverses with the sign of rotation";
    h.needs = kHeading;
    h.variables = {{"C_yr", "C_yr", false, "", -50.0, 50.0, false, 0.0}};
    h.starts = {{-1.0}, {-1e-1}, {-1e-2}, {-1e-3},
                {1e-3}, {1e-2},  {1e-1},  {1.0}};  // both signs, four decades
    h.typical = {{"C_yr", 2e-3, 8e-3, true}};
    // a helical swimmer's head spins slowly (a few rpm): only a head close to the surface
    // (C_yr of order 0.1; the profile integral reaches 2 at a half-immersed head) shows in 40 s
    h.typical_single_flagellum = {{"C_yr", 0.05, 0.15, true}};
    h.steady_table_data = false;
    e.discovery = h;
    return e;
  }();
  return d;
}

void InterfaceLateralForce::attach(const RodNetwork& net) {
  front_ = net.parts.head_front_node;
  center_ = net.parts.head_center_node;
  theta_dof_ = net.thetaIndex(net.parts.head_edge);
}

void InterfaceLateralForce::addForce(const EffectContext& ctx, VecX& force,
                                     JacobianSink* jacobian) const {
  const double c = params_[c_yr_] * ctx.viscosity * params_[radius_] * params_[length_];
  const Vec3 e = nodePosition(ctx.q, center_) - nodePosition(ctx.q, front_);
  const double len = e.norm();
  const Vec3 axis = e / len;
  const Vec3& up = ctx.medium.up;
  const double spin = ctx.rate(theta_dof_);
  // docs/model.md 3.3 (Eq. 4.13): F = -C_yr mu0 R L_head (yhat x (Omega_h ahat))
  const Vec3 direction = up.cross(axis);
  force.segment<3>(3 * center_) += -c * spin * direction;
  if (!jacobian) return;
  const Vec3 d_theta = -(c / ctx.dt) * direction;
  for (int a = 0; a < 3; ++a) jacobian->add(3 * center_ + a, theta_dof_, d_theta(a));
  const Mat3 d_axis = -c * spin * skew(up) * (Mat3::Identity() - axis * axis.transpose()) / len;
  jacobian->addBlock(3 * center_, 3 * center_, d_axis);
  jacobian->addBlock(3 * center_, 3 * front_, -d_axis);
}

}  // namespace flagella
