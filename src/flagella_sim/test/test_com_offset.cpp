// The COM-COV gravity couple (effect com_offset, docs/model.md 5, 8.4.3) against truths that do
// not come from the code under test:
//  1. statics: the two forces sum to zero and their moment about the head centre x_1 is the
//     couple l t^0 x (m_h g) of an offset weight, for random head orientations and gravity
//     directions, with the COM side pulled along gravity;
//  2. the forces are constant vectors: no Jacobian entries, zero finite-difference derivative;
//  3. dynamics of a multi-tail robot in a viscous bath (motor off, head axis horizontal at t = 0):
//     an overdamped rigid body under the torque m_h l |g| cos(phi) (phi the tilt of t^0 below
//     the horizontal) obeys dphi/dt = k cos(phi), i.e. sin(phi(t)) = tanh(k t). The head turns
//     its COM side down, monotonically, toward the vertical; Stokes linearity makes the l < 0 run
//     the mirror image of the l > 0 one; l = 0 leaves the robot at rest;
//  4. the offset is a named parameter that can be changed while running: reversing it reverses
//     the tilt rate from the next step on; an out-of-range value is rejected, nothing changes.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "flagella_sim/effects/com_offset.h"
#include "flagella_sim/rod/rod_kinematics.h"
#include "flagella_sim/simulation/simulation.h"
#include "flagella_sim/simulation/simulation_config.h"
#include "support/temp_dir.h"
#include "support/test_robots.h"

namespace flagella {
namespace {

constexpr double kHeadMass = 0.05;  // m_h [kg]
constexpr double kG = 9.81;         // |g| [m/s^2]
constexpr double kRadToDeg = 180.0 / M_PI;
// d = |x_2 - x_0| at rest of makeLoneHead(0.02) and of the default multi-tail robot
// (|x_0 x_1| = |x_1 x_2| = 0.02 m) [m].
constexpr double kSeparation = 0.04;

Eigen::Matrix3d randomRotation(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  return Eigen::Quaterniond(n(rng), n(rng), n(rng), n(rng)).normalized().toRotationMatrix();
}

Vec3 randomUnit(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  return Vec3(n(rng), n(rng), n(rng)).normalized();
}

/// q of `net` rigidly rotated by R and shifted; positions along the head axis (from x_1) are
/// scaled by `axial_stretch` for the head nodes x_0, x_2 (1 = rigid).
VecX placed(const RodNetwork& net, const Eigen::Matrix3d& R, const Vec3& shift,
            double axial_stretch = 1.0) {
  VecX q = net.restDofs();
  const Vec3 c = net.rest_positions[net.parts.head_center_node];
  for (int i = 0; i < net.numNodes(); ++i) {
    double s = 1.0;
    if (i == net.parts.head_front_node || i == net.parts.joint_node) s = axial_stretch;
    q.segment<3>(3 * i) = R * (c + s * (net.rest_positions[i] - c)) + shift;
  }
  return q;
}

VecX comForce(const ComOffset& e, const RodNetwork& net, const VecX& q, const VecX& q_start,
              const VecX& qdot_start, double dt, double time, const Medium& medium,
              JacobianSink* sink = nullptr) {
  const ReferenceFrames frames = initialFrames(net, q);
  VecX F = VecX::Zero(net.ndof());
  e.addForce({net, q, frames, q_start, qdot_start, dt, time, medium, medium.viscosity()}, F, sink);
  return F;
}

// ---- 1. statics ---------------------------------------------------------------------------------

TEST(ComOffsetStatics, ZeroNetForceAndCoupleOfTheOffsetWeightAtRandomOrientations) {
  std::mt19937 rng(20240611);
  const std::vector<RodNetwork> nets{testing::makeLoneHead(0.02, testing::vpsMaterial()),
                                     testing::makeThreeTailRobot(5)};
  double worst_sum = 0.0, worst_moment = 0.0;
  int checked_sign = 0;
  for (const RodNetwork& net : nets) {
    const RobotParts& p = net.parts;
    for (double l : {3e-3, -5e-3, 0.04}) {
      ComOffset e(kHeadMass);
      e.parameters().set("offset", l);
      e.attach(net);
      for (int trial = 0; trial < 100; ++trial) {
        Medium medium;
        // Half the trials with the usual vertical gravity, half with a random direction.
        medium.gravity = trial % 2 ? Vec3(0.0, 0.0, -kG) : Vec3(kG * randomUnit(rng));
        const VecX q = placed(net, randomRotation(rng), Vec3(0.3, -0.1, 0.7) * (trial % 3));
        const VecX F = comForce(e, net, q, q, VecX::Zero(net.ndof()), 0.01, 0.01, medium);
        const Vec3 x1 = nodePosition(q, p.head_center_node);
        Vec3 sum = Vec3::Zero(), moment = Vec3::Zero();
        for (int i = 0; i < net.numNodes(); ++i) {
          sum += F.segment<3>(3 * i);
          moment += (nodePosition(q, i) - x1).cross(F.segment<3>(3 * i));
          if (i != p.head_front_node && i != p.joint_node) {
            ASSERT_EQ(F.segment<3>(3 * i).norm(), 0.0) << "force on node " << i;
          }
        }
        ASSERT_EQ(F.tail(net.numEdges()).norm(), 0.0) << "generalised force on a twist DOF";
        // docs/model.md 5: couple l t^0 x (m_h g), t^0 from x_0 toward x_1 (toward the tails).
        const Vec3 t0 = (x1 - nodePosition(q, p.head_front_node)).normalized();
        const Vec3 expected = l * t0.cross(kHeadMass * medium.gravity);
        const double scale = kHeadMass * std::abs(l) * kG;  // largest possible couple
        worst_sum = std::max(worst_sum, sum.norm() / (scale / kSeparation));
        worst_moment = std::max(worst_moment, (moment - expected).norm() / scale);
        EXPECT_LT(sum.norm(), 1e-13 * scale / kSeparation);
        EXPECT_LT((moment - expected).norm(), 1e-12 * scale);
        // Sign: the moment turns the COM-side end, sign(l) t^0 from x_1, along gravity.
        const Vec3 com_side = (l > 0 ? 1.0 : -1.0) * t0;
        const double sin2 = t0.cross(medium.gravity.normalized()).squaredNorm();
        if (sin2 > 1e-4) {
          EXPECT_GT(moment.cross(com_side).dot(medium.gravity), 0.0);
          ++checked_sign;
        }
        // The weight +M_a g sits on the COM-side node: x_2 for l > 0, x_0 for l < 0.
        const int com_node = l > 0 ? p.joint_node : p.head_front_node;
        EXPECT_GT(F.segment<3>(3 * com_node).dot(medium.gravity), 0.0);
      }
    }
  }
  std::printf(
      "[com_offset statics] 600 placements: max |sum F| / (m_h |l| g / d) = %.1e, "
      "max |M - l t x m_h g| / (m_h |l| g) = %.1e, sign checked in %d\n",
      worst_sum, worst_moment, checked_sign);
  EXPECT_GT(checked_sign, 500);
}

TEST(ComOffsetStatics, ForceMagnitudeUsesTheRestSeparationOfX0AndX2) {
  // docs/model.md 5: M_a = m_h |l| / d with d = |x_2 - x_0| of the undeformed network, constant:
  // a stretched or compressed head keeps the forces, and the couple scales with the separation.
  const RodNetwork net = testing::makeLoneHead(0.025, testing::vpsMaterial());
  const double d = 0.05;
  const double l = 4e-3;
  ComOffset e(kHeadMass);
  e.parameters().set("offset", l);
  e.attach(net);
  Medium medium;
  medium.gravity = Vec3(0.0, -kG, 0.0);
  std::mt19937 rng(7);
  const double M_a = kHeadMass * l / d;  // [kg]
  for (double stretch : {1.0, 1.05, 0.9}) {
    const VecX q = placed(net, randomRotation(rng), Vec3::Zero(), stretch);
    const VecX F = comForce(e, net, q, q, VecX::Zero(net.ndof()), 0.01, 0.0, medium);
    const Vec3 x0 = nodePosition(q, net.parts.head_front_node);
    const Vec3 x2 = nodePosition(q, net.parts.joint_node);
    const Vec3 F0 = F.segment<3>(3 * net.parts.head_front_node);
    const Vec3 F2 = F.segment<3>(3 * net.parts.joint_node);
    EXPECT_NEAR((F2 - M_a * medium.gravity).norm(), 0.0, 1e-15) << "stretch " << stretch;
    EXPECT_NEAR((F0 + M_a * medium.gravity).norm(), 0.0, 1e-15) << "stretch " << stretch;
    const Vec3 moment = x0.cross(F0) + x2.cross(F2);
    const Vec3 expected = stretch * l * (x2 - x0).normalized().cross(kHeadMass * medium.gravity);
    EXPECT_LT((moment - expected).norm(), 1e-12 * expected.norm()) << "stretch " << stretch;
  }
  // m_h enters linearly.
  ComOffset heavy(3.0 * kHeadMass);
  heavy.parameters().set("offset", l);
  heavy.attach(net);
  const VecX q = net.restDofs();
  const VecX F = comForce(heavy, net, q, q, VecX::Zero(net.ndof()), 0.01, 0.0, medium);
  EXPECT_NEAR(F.segment<3>(3 * net.parts.joint_node).norm(), 3.0 * kHeadMass * l / d * kG, 1e-14);
}

// ---- 2. Jacobian
// ---------------------------------------------------------------------------------

class RecordingSink : public JacobianSink {
 public:
  void add(int, int, double) override { ++entries; }
  void addBlock(int, int, const Mat3&) override { entries += 9; }
  int entries = 0;
};

TEST(ComOffsetJacobian, NoEntriesAndZeroFiniteDifferenceDerivative) {
  const RodNetwork net = testing::makeThreeTailRobot(5);
  std::mt19937 rng(11);
  Medium medium;
  medium.gravity = Vec3(1.0, -9.7, 0.8);
  for (double l : {2e-3, -6e-3}) {
    ComOffset e(kHeadMass);
    e.parameters().set("offset", l);
    e.attach(net);
    const VecX q_start =
        testing::perturbed(net, placed(net, randomRotation(rng), Vec3::Zero()), 2e-3, 0.5, rng);
    const VecX q = testing::perturbed(net, q_start, 1e-3, 0.3, rng);  // non-zero velocity
    const VecX qdot_start = (q - q_start) / 0.01;
    RecordingSink sink;
    const VecX F = comForce(e, net, q, q_start, qdot_start, 0.01, 0.37, medium, &sink);
    ASSERT_GT(F.norm(), 0.0);
    EXPECT_EQ(sink.entries, 0);
    // Central differences in every DOF (positions and twists): the force does not change at all.
    const double h = 1e-6;
    double max_derivative = 0.0;
    for (int i = 0; i < net.ndof(); ++i) {
      VecX qp = q, qm = q;
      qp(i) += h;
      qm(i) -= h;
      const VecX Fp = comForce(e, net, qp, q_start, qdot_start, 0.01, 0.37, medium);
      const VecX Fm = comForce(e, net, qm, q_start, qdot_start, 0.01, 0.37, medium);
      max_derivative = std::max(max_derivative, ((Fp - Fm) / (2.0 * h)).cwiseAbs().maxCoeff());
    }
    std::printf(
        "[com_offset jacobian] l = %+.0e m: %d sink entries, max |dF/dq| (FD) = %.1e, "
        "|F| = %.3e N\n",
        l, sink.entries, max_derivative, F.norm());
    EXPECT_EQ(max_derivative, 0.0);
    // Nor on velocity, time or step size.
    const VecX F_other = comForce(e, net, q, q, VecX::Zero(net.ndof()), 0.002, 5.0, medium);
    EXPECT_EQ((F - F_other).cwiseAbs().maxCoeff(), 0.0);
  }
}

// ---- 3. dynamics
// ---------------------------------------------------------------------------------

// Multi-tail robot built along +z, three tails with spokes at 90, 210, 330 degrees from +x (mirror
// symmetric about x = 0), in a viscous bath (RFT on the tails, Stokes drag on the head,
// docs/model.md 2, 3.1) with vertical +y: the head axis starts horizontal. Motor off; no gravity
// effect, so weight and buoyancy do not act, only the couple (docs/model.md 5).
// - Tails stiff (E = 1 GPa, near PLA's 4.1 GPa in docs/model.md 8.4.1) so the robot turns as one
//   rigid body: VPS tails (1.2 MPa) relax in eta_p L^4/EI ~ 1 s and lag the head.
// - Robot density 10 kg/m^3: the lumped masses (docs/model.md 1.8) are then negligible against the
//   drag (I/(zeta dt) ~ 2e-3); at 1000 kg/m^3 the first implicit step turns 20 % slower.
// - Newton residual tolerance 1e-10: the scale-aware test (docs/model.md 1.10) measures forces
//   against EI/L^2 = 33 N of the stiff tails, while the couple's forces are ~0.04 N.
constexpr double kDt = 0.01;
constexpr double kViscosity = 3.0;    // [Pa s]
constexpr double kTailModulus = 1e9;  // [Pa]
constexpr double kOffset = 3e-3;      // l0 [m]

std::string tiltConfig(double offset) {
  char com[160];
  std::snprintf(com, sizeof com, "  com_offset: {offset: %.17g, head_mass: %.17g}\n", offset,
                kHeadMass);
  char medium[160];
  std::snprintf(medium, sizeof medium,
                "medium: {viscosity: %.17g, density: 1000, up: [0, 1, 0], gravity: [0, %.17g, "
                "0]}\n",
                kViscosity, -kG);
  char simulation[160];
  std::snprintf(simulation, sizeof simulation,
                "simulation: {dt: %.17g, duration: 10, output_interval: 0.1}\n", kDt);
  return std::string(
             "robot: {n_tails: 3, tail_length: 0.05, tail_edges: 5, head_radius: 0.02, "
             "spoke_phase_deg: 90, density: 10, youngs_modulus: " +
             std::to_string(kTailModulus) + "}\n") +
         medium +
         "effects:\n"
         "  rft: {log_form: \"L/r0\"}\n"
         "  stokes_head: {C_t: 1.0, C_r: 1.0}\n" +
         com + "motor: {omega_rpm: 0}\n" + simulation + "solver: {residual_tolerance: 1.0e-10}\n";
}

Simulation tiltSimulation(double offset) {
  return Simulation(parseSimulationConfig(YAML::Load(tiltConfig(offset)), "test_com_offset"));
}

Vec3 headAxis(const Simulation& sim) {  // t^0, from x_0 toward x_1
  const RobotParts& p = sim.network().parts;
  return (nodePosition(sim.state().q, p.head_center_node) -
          nodePosition(sim.state().q, p.head_front_node))
      .normalized();
}

/// Tilt of t^0 below the horizontal, toward gravity [rad]: 90 deg minus the angle (t^0, g).
double tilt(const Simulation& sim) {
  return std::asin(std::clamp(headAxis(sim).dot(Vec3(0.0, -1.0, 0.0)), -1.0, 1.0));
}

/// Angular velocity of the head axis, t x dt/dt, from the node rates of x_0, x_1 [rad/s].
Vec3 axisAngularVelocity(const Simulation& sim) {
  const RobotParts& p = sim.network().parts;
  const VecX& q = sim.state().q;
  const VecX& qdot = sim.state().qdot;
  const Vec3 edge = nodePosition(q, p.head_center_node) - nodePosition(q, p.head_front_node);
  const Vec3 t = edge.normalized();
  const Vec3 rate =
      qdot.segment<3>(3 * p.head_center_node) - qdot.segment<3>(3 * p.head_front_node);
  return t.cross(rate) / edge.norm();
}

struct TiltRun {
  std::vector<double> time, phi;
  Vec3 first_omega = Vec3::Zero();  ///< angular velocity of t^0 after the first step
  Vec3 torque = Vec3::Zero();       ///< closed-form couple at t = 0
  double max_out_of_plane = 0.0;    ///< max |t^0_x|
  double max_displacement = 0.0;    ///< max |q - q(0)|
};

TiltRun runTilt(double offset, double duration) {
  Simulation sim = tiltSimulation(offset);
  TiltRun r;
  const VecX q0 = sim.state().q;
  r.torque = offset * headAxis(sim).cross(kHeadMass * Vec3(0.0, -kG, 0.0));
  r.time.push_back(0.0);
  r.phi.push_back(tilt(sim));
  const long steps = std::lround(duration / kDt);
  for (long k = 0; k < steps; ++k) {
    sim.step();
    if (k == 0) r.first_omega = axisAngularVelocity(sim);
    r.time.push_back(sim.time());
    r.phi.push_back(tilt(sim));
    r.max_out_of_plane = std::max(r.max_out_of_plane, std::abs(headAxis(sim).x()));
    r.max_displacement = std::max(r.max_displacement, (sim.state().q - q0).cwiseAbs().maxCoeff());
  }
  return r;
}

double phiAt(const TiltRun& r, double t) { return r.phi[std::lround(t / kDt)]; }

TEST(ComOffsetDynamics, HeadTurnsItsComSideDownTowardTheVertical) {
  constexpr double kDuration = 3.0;
  const TiltRun up = runTilt(kOffset, kDuration);     // COM toward the tails: tails go down
  const TiltRun down = runTilt(-kOffset, kDuration);  // COM toward the nose: nose goes down
  const TiltRun none = runTilt(0.0, kDuration);

  // Initial response: the axis turns about the closed-form couple m_h l t x g (docs/model.md 5).
  for (const TiltRun* r : {&up, &down}) {
    const double cos_angle =
        r->first_omega.dot(r->torque) / (r->first_omega.norm() * r->torque.norm());
    std::printf(
        "[com_offset dynamics] first step: |omega| = %.4e rad/s, cos(omega, torque) = "
        "%.6f\n",
        r->first_omega.norm(), cos_angle);
    EXPECT_GT(cos_angle, 0.999);
  }

  // Monotonic: every step turns the COM side (sign(l) t^0) further toward gravity.
  for (size_t i = 1; i < up.phi.size(); ++i) {
    ASSERT_GT(up.phi[i], up.phi[i - 1]) << "t = " << up.time[i];
    ASSERT_LT(down.phi[i], down.phi[i - 1]) << "t = " << down.time[i];
  }

  // Overdamped rigid rotor, dphi/dt = k cos(phi): sin(phi) = tanh(k t), k from phi(0.2 s).
  constexpr double kFitTime = 0.2;
  const double k = std::atanh(std::sin(phiAt(up, kFitTime))) / kFitTime;
  std::printf("[com_offset dynamics] k = %.4f 1/s from phi(%.1f s) = %.3f deg\n", k, kFitTime,
              phiAt(up, kFitTime) * kRadToDeg);
  std::printf(
      "   t [s]   phi(+l) [deg]   phi(-l) [deg]   asin(tanh(k t)) [deg]   angle(t0,g) "
      "(+l) [deg]\n");
  double worst_fit = 0.0, worst_mirror = 0.0;
  for (double t : {0.5, 1.0, 1.5, 2.0, 2.5, 3.0}) {
    const double predicted = std::asin(std::tanh(k * t));
    const double p_up = phiAt(up, t), p_down = phiAt(down, t);
    std::printf("   %4.1f   %13.3f   %13.3f   %21.3f   %22.3f\n", t, p_up * kRadToDeg,
                p_down * kRadToDeg, predicted * kRadToDeg, 90.0 - p_up * kRadToDeg);
    worst_fit = std::max(worst_fit, std::abs(p_up - predicted));
    worst_mirror = std::max(worst_mirror, std::abs(p_up + p_down));
  }
  std::printf(
      "[com_offset dynamics] max |phi - asin(tanh(k t))| = %.3f deg, max |phi(+l) + "
      "phi(-l)| = %.3f deg, max |t0_x| = %.1e / %.1e\n",
      worst_fit * kRadToDeg, worst_mirror * kRadToDeg, up.max_out_of_plane, down.max_out_of_plane);
  EXPECT_LT(worst_fit * kRadToDeg, 0.3);
  EXPECT_LT(worst_mirror * kRadToDeg, 0.01);
  // The first step already turns at the rate k cos(0) of the law (no lag: masses are negligible).
  EXPECT_NEAR(up.first_omega.norm() / k, 1.0, 0.01);
  // Toward the vertical equilibrium: the angle between t^0 and g falls from 90 deg below 15 deg.
  EXPECT_GT(phiAt(up, kDuration) * kRadToDeg, 75.0);
  EXPECT_LT(phiAt(down, kDuration) * kRadToDeg, -75.0);
  // The turn stays in the vertical plane of the axis (the robot is mirror symmetric about x = 0).
  EXPECT_LT(up.max_out_of_plane, 1e-9);
  EXPECT_LT(down.max_out_of_plane, 1e-9);

  // l = 0: no couple, nothing moves.
  std::printf("[com_offset dynamics] l = 0: max |phi| = %.1e rad, max |q - q0| = %.1e\n",
              std::max(std::abs(*std::max_element(none.phi.begin(), none.phi.end())),
                       std::abs(*std::min_element(none.phi.begin(), none.phi.end()))),
              none.max_displacement);
  EXPECT_LT(none.max_displacement, 1e-12);
  EXPECT_LT(std::abs(none.phi.back()), 1e-12);
  EXPECT_EQ(none.first_omega.norm(), 0.0);
}

TEST(ComOffsetDynamics, TurnRateIsLinearInHeadMassTimesOffset) {
  // Stokes flow is linear: the initial turn rate scales with the couple m_h l |g| (docs/model.md
  // 5), so halving l halves it and doubling m_h doubles it.
  auto firstRate = [](double offset, double head_mass) {
    Simulation sim = tiltSimulation(offset);
    sim.setParameter("effects.com_offset.head_mass", head_mass);
    sim.step();
    return axisAngularVelocity(sim).x();  // t x g = +x |g| for t = +z, g = -y
  };
  const double base = firstRate(kOffset, kHeadMass);
  const double half_offset = firstRate(0.5 * kOffset, kHeadMass);
  const double double_mass = firstRate(kOffset, 2.0 * kHeadMass);
  const double negative = firstRate(-2.0 * kOffset, kHeadMass);
  std::printf(
      "[com_offset linearity] omega_x: base %.6f, l/2 %.6f (x%.5f), 2 m_h %.6f (x%.5f), "
      "-2 l %.6f (x%.5f) rad/s\n",
      base, half_offset, half_offset / base, double_mass, double_mass / base, negative,
      negative / base);
  EXPECT_GT(base, 0.0);
  EXPECT_NEAR(half_offset / base, 0.5, 1e-3);
  EXPECT_NEAR(double_mass / base, 2.0, 4e-3);
  EXPECT_NEAR(negative / base, -2.0, 4e-3);
}

// ---- 4. settable while running
// -------------------------------------------------------------------

TEST(ComOffsetParameter, ReversingTheOffsetWhileRunningReversesTheTiltRate) {
  Simulation sim = tiltSimulation(kOffset);
  sim.run(0.5);
  const double phi_a = tilt(sim);
  sim.step();
  const double phi_b = tilt(sim);
  const double rate_before = (phi_b - phi_a) / kDt;
  ASSERT_GT(rate_before, 0.0);

  sim.setParameter("effects.com_offset.offset", -kOffset);
  EXPECT_EQ(sim.parameter("effects.com_offset.offset"), -kOffset);
  sim.step();
  const double phi_c = tilt(sim);
  const double rate_after = (phi_c - phi_b) / kDt;
  // Stokes linearity: same |torque| (cos(phi) barely changes in a step), opposite sign, from the
  // very next step.
  std::printf(
      "[com_offset set] tilt %.3f deg: rate before %.5f rad/s, first step after %.5f "
      "rad/s (ratio %.4f)\n",
      phi_b * kRadToDeg, rate_before, rate_after, rate_after / rate_before);
  EXPECT_LT(rate_after, 0.0);
  EXPECT_NEAR(rate_after / rate_before, -1.0, 0.01);
  double phi_prev = phi_c;
  for (int k = 0; k < 30; ++k) {
    sim.step();
    EXPECT_LT(tilt(sim), phi_prev) << "step " << k << " after the change";
    phi_prev = tilt(sim);
  }
}

TEST(ComOffsetParameter, OutOfRangeOffsetIsRejectedAndChangesNothing) {
  Simulation sim = tiltSimulation(kOffset);
  Simulation twin = tiltSimulation(kOffset);
  sim.run(0.2);
  twin.run(0.2);
  const RodState before = sim.state();
  for (double bad : {0.2, -0.1 - 1e-9, std::nan("")}) {
    const std::string msg = testing::errorMessageOf<ConfigError>(
        [&] { sim.setParameter("effects.com_offset.offset", bad); });
    EXPECT_NE(msg.find("effects.com_offset.offset"), std::string::npos) << msg;
    EXPECT_NE(msg.find("[-0.1, 0.1]"), std::string::npos) << msg;
    EXPECT_EQ(sim.parameter("effects.com_offset.offset"), kOffset);
  }
  EXPECT_EQ(sim.time(), before.time);
  EXPECT_EQ((sim.state().q - before.q).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((sim.state().qdot - before.qdot).cwiseAbs().maxCoeff(), 0.0);
  // The run goes on exactly as one that never saw the rejected values.
  sim.run(0.1);
  twin.run(0.1);
  EXPECT_EQ((sim.state().q - twin.state().q).cwiseAbs().maxCoeff(), 0.0);
}

}  // namespace
}  // namespace flagella
