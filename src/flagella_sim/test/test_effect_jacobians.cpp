// Every effect's force Jacobian against central finite differences of its force, at random
// states with non-zero velocities (docs/model.md 2, 3.1, 3.3).
#include <gtest/gtest.h>

#include <random>

#include "flagella_sim/core/geometry.h"
#include "flagella_sim/effects/com_offset.h"
#include "flagella_sim/effects/constant_load.h"
#include "flagella_sim/effects/granular_jamming.h"
#include "flagella_sim/effects/granular_yield.h"
#include "flagella_sim/effects/gravity.h"
#include "flagella_sim/effects/head_restraint.h"
#include "flagella_sim/effects/interface_lateral_force.h"
#include "flagella_sim/effects/rft_drag.h"
#include "flagella_sim/effects/stokes_head_drag.h"
#include "flagella_sim/effects/tail_weight.h"
#include "flagella_sim/rod/rod_kinematics.h"
#include "support/test_robots.h"

namespace flagella {
namespace {

class DenseSink : public JacobianSink {
 public:
  explicit DenseSink(int n) : J(MatX::Zero(n, n)) {}
  void add(int row, int col, double value) override { J(row, col) += value; }
  MatX J;
};

struct Fixture {
  RodNetwork net;
  Medium medium;
  VecX q_start, qdot_start, q;
  ReferenceFrames frames_start;
  double dt = 0.01;
};

Fixture makeFixture(unsigned seed) {
  Fixture f{testing::makeThreeTailRobot(6), Medium(), {}, {}, {}, {}, 0.01};
  f.medium.parameters().set("viscosity", 2.5);
  f.medium.up = Vec3(0.1, 1.0, 0.05).normalized();
  f.medium.profile.enabled = true;
  f.medium.profile.onset_height = 0.005;
  f.medium.profile.length_scale = 0.016;
  std::mt19937 rng(seed);
  f.q_start = testing::perturbed(f.net, f.net.restDofs(), 2e-3, 0.5, rng);
  f.qdot_start = VecX::Zero(f.net.ndof());
  f.frames_start = initialFrames(f.net, f.q_start);
  f.q = testing::perturbed(f.net, f.q_start, 1e-3, 0.3, rng);
  return f;
}

VecX forceAt(const Effect& e, const Fixture& f, const VecX& q) {
  const ReferenceFrames fr = transportFrames(f.net, q, f.frames_start);
  VecX F = VecX::Zero(f.net.ndof());
  e.as<ForceLaw>()->addForce(
      {f.net, q, fr, f.q_start, f.qdot_start, f.dt, f.dt, f.medium, f.medium.viscosity()}, F,
      nullptr);
  return F;
}

void expectJacobianMatchesFiniteDifferences(Effect& e, unsigned seed) {
  const Fixture f = makeFixture(seed);
  e.attach(f.net);
  const ReferenceFrames fr = transportFrames(f.net, f.q, f.frames_start);
  DenseSink sink(f.net.ndof());
  VecX F = VecX::Zero(f.net.ndof());
  ASSERT_NE(e.as<ForceLaw>(), nullptr) << e.name() << " is not a force";
  e.as<ForceLaw>()->addForce(
      {f.net, f.q, fr, f.q_start, f.qdot_start, f.dt, f.dt, f.medium, f.medium.viscosity()}, F,
      &sink);
  ASSERT_TRUE(F.allFinite());
  const double h = 1e-7;
  MatX J_fd(f.net.ndof(), f.net.ndof());
  for (int i = 0; i < f.net.ndof(); ++i) {
    VecX qp = f.q, qm = f.q;
    qp(i) += h;
    qm(i) -= h;
    J_fd.col(i) = (forceAt(e, f, qp) - forceAt(e, f, qm)) / (2 * h);
  }
  const double scale = std::max(J_fd.cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((sink.J - J_fd).cwiseAbs().maxCoeff(), 1e-6 * scale)
      << e.name() << ": max |J - J_fd| relative to max |J_fd| " << scale;
}

TEST(EffectJacobians, RftViscousLogForm) {
  RftDrag e(RftLogForm::kLengthOverRadius);
  for (unsigned s : {1u, 2u}) expectJacobianMatchesFiniteDifferences(e, s);
}

TEST(EffectJacobians, RftGranularWithInterfaceViscosityProfile) {
  RftDrag e(RftLogForm::kTwoLengthOverRadius, true);
  for (unsigned s : {3u, 4u}) expectJacobianMatchesFiniteDifferences(e, s);
}

TEST(EffectJacobians, StokesHeadDrag) {
  StokesHeadDrag e(2.42, 0.039, 0.02);
  expectJacobianMatchesFiniteDifferences(e, 5);
  StokesHeadDrag sphere(2.42, 0.039, 0.02, 1.0);  // pitch and yaw resisted too
  for (unsigned s : {5u, 16u}) expectJacobianMatchesFiniteDifferences(sphere, s);
}

// docs/model.md 3.1: a head turning rigidly about x_1 at Omega feels the torque -C_r 8 pi mu a^3
// Omega about every axis when tilt_drag = 1 (a sphere), and about the spin axis alone when it is 0;
// the head drag adds no net force to a pure rotation.
TEST(HeadDrag, TorqueOfARigidRotationAboutEachAxisMatchesTheSphere) {
  const RodNetwork net = testing::makeThreeTailRobot(4);
  Medium medium;
  medium.parameters().set("viscosity", 1.03);
  const double C_r = 1.37, a = 0.018, dt = 1e-3, omega = 0.7;  // Omega dt = 7e-4 rad
  const double k = C_r * 8.0 * M_PI * 1.03 * a * a * a;
  const RobotParts& parts = net.parts;
  const VecX q_start = net.restDofs();
  const Vec3 centre = nodePosition(q_start, parts.head_center_node);
  const Vec3 spin =
      (nodePosition(q_start, parts.joint_node) - nodePosition(q_start, parts.head_front_node))
          .normalized();
  const Vec3 pitch = anyPerpendicular(spin), yaw = spin.cross(pitch);
  for (double tilt_drag : {1.0, 0.0}) {
    StokesHeadDrag e(1.8, C_r, a, tilt_drag);
    e.attach(net);
    for (const Vec3& n : {spin, pitch, yaw}) {
      // x_0 and x_2 turned about n through x_1 by Omega dt; the head's twist by its spin part
      VecX q = q_start;
      const Eigen::AngleAxisd turn(omega * dt, n);
      for (int node : {parts.head_front_node, parts.joint_node})
        q.segment<3>(3 * node) = centre + turn * (nodePosition(q_start, node) - centre);
      q(net.thetaIndex(parts.head_edge)) += omega * dt * n.dot(spin);
      const ReferenceFrames fr = initialFrames(net, q);
      VecX F = VecX::Zero(net.ndof());
      e.addForce({net, q, fr, q_start, VecX::Zero(net.ndof()), dt, dt, medium, 1.03}, F, nullptr);
      Vec3 torque = Vec3::Zero(), net_force = Vec3::Zero();
      for (int node : {parts.head_front_node, parts.head_center_node, parts.joint_node}) {
        torque += (nodePosition(q_start, node) - centre).cross(F.segment<3>(3 * node));
        net_force += F.segment<3>(3 * node);
      }
      torque += F(net.thetaIndex(parts.head_edge)) * spin;  // the spin's generalised force
      const double resisted = n == spin ? 1.0 : tilt_drag;
      // a rotation by Omega dt in one step: the implicit rate is sin(Omega dt)/dt off the axis
      const double rate = n == spin ? omega : std::sin(omega * dt) / dt;
      EXPECT_LT((torque + resisted * k * rate * n).norm(), 1e-12 * k * omega)
          << "tilt_drag " << tilt_drag << ", axis " << n.transpose();
      EXPECT_LT(net_force.norm(), 1e-12 * k * omega / a);
    }
  }
}

TEST(EffectJacobians, InterfaceLateralForceIsNonSymmetric) {
  InterfaceLateralForce e(6.0, 0.016, 0.06);
  expectJacobianMatchesFiniteDifferences(e, 6);
  // The force couples head spin (a twist column) into position rows only: non-symmetric.
  const Fixture f = makeFixture(6);
  e.attach(f.net);
  DenseSink sink(f.net.ndof());
  VecX F = VecX::Zero(f.net.ndof());
  const ReferenceFrames fr = transportFrames(f.net, f.q, f.frames_start);
  e.addForce({f.net, f.q, fr, f.q_start, f.qdot_start, f.dt, f.dt, f.medium, f.medium.viscosity()},
             F, &sink);
  EXPECT_GT((sink.J - sink.J.transpose()).cwiseAbs().maxCoeff(), 0.0);
}

TEST(EffectJacobians, HeadRestraint) {
  HeadRestraint e(3.0, 0.7);
  for (unsigned s : {9u, 10u}) expectJacobianMatchesFiniteDifferences(e, s);
}

TEST(EffectJacobians, ConstantForcesHaveZeroJacobian) {
  Gravity g(1100.0);
  expectJacobianMatchesFiniteDifferences(g, 7);
  ConstantLoad c;
  c.addNodeForce(1, Vec3(1, 2, 3));
  expectJacobianMatchesFiniteDifferences(c, 8);
  TailWeight w;
  w.parameters().set("extra_density", 40.0);
  expectJacobianMatchesFiniteDifferences(w, 16);
}

TEST(EffectJacobians, GranularYield) {
  // Head speeds in the fixture are ~0.1 m/s: v_s = 1e-2 m/s (the top of its range) keeps the
  // force off saturation, v_s = 1e-6 m/s is the saturated default.
  for (double v_s : {1e-2, 1e-6}) {
    GranularYield e;
    e.parameters().set("yield_force", 2e-3);
    e.parameters().set("velocity_scale", v_s);
    for (unsigned s : {11u, 12u}) expectJacobianMatchesFiniteDifferences(e, s);
  }
}

TEST(EffectJacobians, GranularJammingWithResistance) {
  GranularJamming e;
  e.parameters().set("stiffness", 5.0);
  e.parameters().set("velocity_scale", 5e-3);
  e.setPushedDistance(4e-4);  // s > 0: resistance k_j s = 2 mN
  ASSERT_GT(e.resistance(), 0.0);
  for (unsigned s : {13u, 14u}) expectJacobianMatchesFiniteDifferences(e, s);
}

TEST(EffectJacobians, ComOffsetHasZeroJacobian) {
  ComOffset e(0.05);
  e.parameters().set("offset", 3e-3);
  expectJacobianMatchesFiniteDifferences(e, 15);
}

TEST(EffectJacobians, IntegratedLateralCoefficientMatchesDirectQuadrature) {
  // Independent midpoint-rule quadrature of I(h/R, k) = int sin(phi) mu(R sin phi)/mu0 dphi.
  const double h = 0.7, k = 20.0;
  const int n = 200000;
  double I = 0.0;
  for (int i = 0; i < n; ++i) {
    const double phi = 2.0 * M_PI * (i + 0.5) / n;
    I += std::sin(phi) / (1.0 + std::exp(k * (std::sin(phi) - h))) * 2.0 * M_PI / n;
  }
  EXPECT_LT(I, 0.0);  // the upper arc sits in air (docs/model.md 3.3)
  EXPECT_NEAR(integratedLateralCoefficient(h, k), -I, 1e-9);
  // Without an interface (h -> infinity) the integral vanishes by symmetry.
  EXPECT_NEAR(integratedLateralCoefficient(1e3, k), 0.0, 1e-12);
}

}  // namespace
}  // namespace flagella
