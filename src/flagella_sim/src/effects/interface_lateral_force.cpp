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
    const double y = std::sin(phi);  // height over R of the surface point (spec 3.3)
    sum += std::sin(phi) / (1.0 + std::exp(sharpness * (y - onset_over_radius)));
  }
  return -sum * 2.0 * M_PI / kQuadraturePoints;
}

InterfaceLateralForce::InterfaceLateralForce(double C_yr, double head_radius, double head_length)
    : Effect(kName) {
  c_yr_ =
      params_.declare("C_yr", C_yr, -1e4, 1e4, "", "lateral rotation-induced force coefficient");
  radius_ = params_.declare("head_radius", head_radius, 1e-6, 10.0, "m", "head radius R");
  length_ = params_.declare("head_length", head_length, 1e-6, 10.0, "m", "head length L_head");
}

void InterfaceLateralForce::attach(const RodNetwork& net) {
  front_ = net.parts.head_front_node;
  center_ = net.parts.head_center_node;
  theta_dof_ = net.thetaIndex(net.parts.head_edge);
}

void InterfaceLateralForce::addForce(const EffectContext& ctx, VecX& force,
                                     JacobianSink* jacobian) const {
  const double c = params_[c_yr_] * ctx.medium.viscosity() * params_[radius_] * params_[length_];
  const Vec3 e = nodePosition(ctx.q, center_) - nodePosition(ctx.q, front_);
  const double len = e.norm();
  const Vec3 axis = e / len;
  const Vec3& up = ctx.medium.up;
  const double spin = ctx.rate(theta_dof_);
  // spec 3.3 (Eq. 4.13): F = -C_yr mu0 R L_head (yhat x (Omega_h ahat))
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
