// Static benchmarks of the DER network (docs/model.md 1.2-1.5, 1.10) against closed-form beam
// theory: a clamped cantilever under a uniform transverse load and under a tip load
// (Euler-Bernoulli), and a clamped rod under an end torque (Saint-Venant torsion). Equilibrium is
// reached with the implicit stepper (docs/model.md 1.10) using a huge time step, so the inertia
// term m/dt^2 is negligible.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "flagella_sim/actuation/motor_command.h"
#include "flagella_sim/effects/constant_load.h"
#include "flagella_sim/effects/medium.h"
#include "flagella_sim/solver/implicit_stepper.h"
#include "flagella_sim/solver/newton_options.h"
#include "support/test_robots.h"

namespace flagella {
namespace {

// Rod of the benchmarks: VPS tail material (docs/model.md 8.1), 10 cm long.
constexpr double kRodLength = 0.1;  // L [m]
// Stiffnesses recomputed here from docs/model.md 1.4, independently of RodMaterial.
constexpr double kYoungsModulus = 1.2e6;  // E [Pa]
constexpr double kPoissonRatio = 0.5;     // nu
constexpr double kRadius = 3.2e-3;        // r0 [m]

// A step of 1e3 s makes m/dt^2 ~ 1e-10 N/m against bending stiffnesses EI/dl^3 ~ 10 N/m, so
// every step is a static Newton solve; the extra steps only confirm nothing moves any more.
constexpr double kStaticDt = 1e3;
constexpr int kStaticSteps = 3;
// Scaled Newton residual: far below the loads used (load/scale ~ 1e-4 .. 1e-2).
constexpr double kStaticResidualTolerance = 1e-12;

// Target tip deflection of the bending benchmarks, as a fraction of L. Small enough that the
// geometric nonlinearity (relative size ~(delta/L)^2 ~ 1e-5) is far below the tolerance.
constexpr double kTipDeflectionFraction = 3e-3;
// Bending vs Euler-Bernoulli with the effective length L - dl/2 (see CantileverUniformLoad):
// the residual discretisation error is dl^2/(2 L^2) <= 3.2e-4 for >= 40 edges, and the geometric
// nonlinearity ~1e-5. A wrong clamp position (L or L - dl) is off by ~1.5-2 dl/L >= 2.5 %.
constexpr double kBendingTolerance = 0.01;
// Against the exact linear solution of the discrete rod (derived in effectiveBeamLength): only the
// geometric nonlinearity (~(delta/L)^2 ~ 1e-5) and the Newton residual remain.
constexpr double kDiscreteLinearTolerance = 1e-4;
// Twist of a straight rod is exactly linear in the torque (tau = theta^F - theta^E, m_ref = 0);
// only the Newton residual (1e-12 relative) limits the agreement.
constexpr double kTwistTolerance = 1e-6;
// Under pure twist the centreline must stay put (m): round-off level against dl ~ 2 mm.
constexpr double kStraightnessTolerance = 1e-12;

double secondMomentOfArea() { return M_PI * std::pow(kRadius, 4) / 4.0; }
double bendingStiffness() { return kYoungsModulus * secondMomentOfArea(); }  // EI
double twistingStiffness() {  // GJ with J = pi r0^4 / 2 [CORR-1], G = E / (2 (1 + nu))
  const double G = kYoungsModulus / (2.0 * (1.0 + kPoissonRatio));
  return G * M_PI * std::pow(kRadius, 4) / 2.0;
}

// Clamps the first edge: both of its nodes and its twist angle theta^0.
void clampFirstEdge(RodNetwork& net) {
  for (int node : {0, 1})
    for (int a = 0; a < 3; ++a) net.fixed_dof[RodNetwork::positionIndex(node) + a] = true;
  net.fixed_dof[net.thetaIndex(0)] = true;
}

NewtonOptions staticOptions() {
  NewtonOptions o;
  const double EI = bendingStiffness();
  o.force_scale = EI / (kRodLength * kRodLength);
  o.moment_scale = EI / kRodLength;
  o.length_scale = kRodLength;
  o.residual_tolerance = kStaticResidualTolerance;
  o.step_tolerance = 1e-15;
  return o;
}

// Equilibrium of the clamped rod under the given constant load.
RodState solveStatic(const RodNetwork& net, std::unique_ptr<ConstantLoad> load) {
  std::vector<EffectPtr> effects;
  effects.push_back(std::move(load));
  ImplicitStepper stepper(net, std::move(effects), Medium(), staticOptions());
  RodState state = stepper.initialState();
  const ConstantMotor no_motor(0.0);
  for (int k = 0; k < kStaticSteps; ++k) stepper.step(state, kStaticDt, no_motor);
  return state;
}

Vec3 displacement(const RodNetwork& net, const RodState& s, int node) {
  return nodePosition(s.q, node) - net.rest_positions[node];
}

// Effective cantilever length of the discrete rod clamped by its first edge.
//
// The clamp fixes the direction of edge 0, i.e. the slope at its midpoint s = dl/2, and the first
// bending spring (node 1) integrates curvature over its Voronoi cell, which starts exactly at that
// midpoint. For a straight rod the moment in spring i equals the moment about x_i of all node
// loads beyond it, so phi_i = dl M(x_i)/EI and the tip deflection is sum_i dl M(x_i)(L - x_i)/EI
// over the interior nodes: the trapezoid rule of the unit-load integral with the half cell at the
// clamp missing. With Voronoi-lumped loads this sums exactly to w L^2 (L - dl)^2/(8 EI) (uniform)
// and P L (L - dl)(L - dl/2)/(3 EI) (tip load): both equal the Euler-Bernoulli values at
// L_eff = L - dl/2 up to relative dl^2/(2 L^2) and dl^2/(4 L^2). Clamping at node 0 (L) or at
// node 1 (L - dl) would be off by ~2 dl/L (uniform) or ~1.5 dl/L (tip load): 2.5-5 % here.
double effectiveBeamLength(int edges) { return kRodLength - 0.5 * kRodLength / edges; }

class CantileverTest : public ::testing::TestWithParam<int> {};

TEST_P(CantileverTest, UniformLoadMatchesEulerBernoulli) {
  const int edges = GetParam();
  RodNetwork net = testing::makeStraightRod(edges, kRodLength, testing::vpsMaterial());
  clampFirstEdge(net);
  const double EI = bendingStiffness();
  const double L_eff = effectiveBeamLength(edges);
  // Load per length giving the target tip deflection for w L^4/(8 EI).
  const double w = 8.0 * EI * kTipDeflectionFraction * kRodLength / std::pow(kRodLength, 4);
  const double dl = kRodLength / edges;
  // Both material bending directions and an oblique plane: the circular section is isotropic.
  const std::vector<Vec3> directions = {Vec3(1.0, 0.0, 0.0), Vec3(0.0, 1.0, 0.0),
                                        Vec3(1.0, 1.0, 0.0).normalized()};
  for (const Vec3& dir : directions) {
    SCOPED_TRACE("load direction (" + std::to_string(dir.x()) + ", " + std::to_string(dir.y()) +
                 ")");
    auto load = std::make_unique<ConstantLoad>();
    for (int i = 0; i <= edges; ++i) {
      const double voronoi = (i == 0 || i == edges) ? 0.5 * dl : dl;  // half an edge at the tip
      load->addNodeForce(i, w * voronoi * dir);
    }
    const RodState s = solveStatic(net, std::move(load));
    const Vec3 d_tip = displacement(net, s, edges);
    const double tip = d_tip.dot(dir);
    const double expected = w * std::pow(L_eff, 4) / (8.0 * EI);
    const double rel_error = std::abs(tip - expected) / expected;
    std::printf(
        "[cantilever uniform, %d edges, dir (%.3f, %.3f)] tip %.6e m, EB(L - dl/2) %.6e m, "
        "rel err %.2e\n",
        edges, dir.x(), dir.y(), tip, expected, rel_error);
    EXPECT_LT(rel_error, kBendingTolerance);
    const double discrete = w * std::pow(kRodLength * (kRodLength - dl), 2) / (8.0 * EI);
    EXPECT_NEAR(tip, discrete, kDiscreteLinearTolerance * discrete);
    // The deflection stays in the load plane (spanned by dir and the rod axis) and the clamp holds.
    const Vec3 off_plane = d_tip - d_tip.dot(dir) * dir - d_tip.z() * Vec3::UnitZ();
    EXPECT_LT(off_plane.norm(), 1e-9 * tip);
    EXPECT_EQ(displacement(net, s, 1).norm(), 0.0);
    // Deflection profile, not only the tip: y(s) = w/(24 EI) s^2 (6 L^2 - 4 L s + s^2) from the
    // effective clamp s = z - dl/2; checked at mid-span with the same tolerance on the tip scale.
    const int mid = edges / 2;
    const double s_mid = mid * dl - 0.5 * dl;
    const double y_mid = w / (24.0 * EI) * s_mid * s_mid *
                         (6.0 * L_eff * L_eff - 4.0 * L_eff * s_mid + s_mid * s_mid);
    EXPECT_NEAR(displacement(net, s, mid).dot(dir), y_mid, kBendingTolerance * expected);
  }
}

TEST_P(CantileverTest, TipLoadMatchesEulerBernoulli) {
  const int edges = GetParam();
  RodNetwork net = testing::makeStraightRod(edges, kRodLength, testing::vpsMaterial());
  clampFirstEdge(net);
  const double EI = bendingStiffness();
  const double L_eff = effectiveBeamLength(edges);
  const double P = 3.0 * EI * kTipDeflectionFraction * kRodLength / std::pow(kRodLength, 3);
  auto load = std::make_unique<ConstantLoad>();
  load->addNodeForce(edges, Vec3(P, 0.0, 0.0));
  const RodState s = solveStatic(net, std::move(load));
  const double tip = displacement(net, s, edges).x();
  const double expected = P * std::pow(L_eff, 3) / (3.0 * EI);
  const double rel_error = std::abs(tip - expected) / expected;
  std::printf("[cantilever tip load, %d edges] tip %.6e m, EB(L - dl/2) %.6e m, rel err %.2e\n",
              edges, tip, expected, rel_error);
  EXPECT_LT(rel_error, kBendingTolerance);
  const double dl = kRodLength / edges;
  const double discrete = P * kRodLength * (kRodLength - dl) * (kRodLength - 0.5 * dl) / (3.0 * EI);
  EXPECT_NEAR(tip, discrete, kDiscreteLinearTolerance * discrete);
}

// 40 and 60 edges (dl/L = 2.5 % and 1.7 %): the agreement must not hinge on one mesh.
INSTANTIATE_TEST_SUITE_P(Meshes, CantileverTest, ::testing::Values(40, 60));

TEST(StaticBenchmarks, EndTorqueTwistsLinearly) {
  const int edges = 50;
  RodNetwork net = testing::makeStraightRod(edges, kRodLength, testing::vpsMaterial());
  clampFirstEdge(net);
  const double GJ = twistingStiffness();
  const double dl = kRodLength / edges;
  // Twist springs sit at the interior nodes 1..N-1, each with Voronoi length dl, so the twisted
  // length is the distance between the midpoints of the first and the last edge.
  const double L_eff = (edges - 1) * dl;
  const double M = 0.2 * GJ / L_eff;  // 0.2 rad total twist, far below any torsional buckling
  const int last = edges - 1;
  auto load = std::make_unique<ConstantLoad>();
  load->addEdgeTorque(net, last, M);
  const RodState s = solveStatic(net, std::move(load));

  const double theta0 = s.q(net.thetaIndex(0));
  const double twist = s.q(net.thetaIndex(last)) - theta0;
  const double expected = M * L_eff / GJ;
  const double rel_error = std::abs(twist - expected) / expected;
  std::printf("[end torque] twist %.10e rad, M L_eff/GJ %.10e rad, rel err %.2e\n", twist, expected,
              rel_error);
  EXPECT_LT(rel_error, kTwistTolerance);
  // Uniform torque: theta^j - theta^0 = M (j dl)/GJ for every edge (linear along the rod).
  double max_profile_error = 0.0;
  for (int j = 0; j < edges; ++j) {
    const double theta_j = s.q(net.thetaIndex(j)) - theta0;
    max_profile_error = std::max(max_profile_error, std::abs(theta_j - M * j * dl / GJ));
  }
  EXPECT_LT(max_profile_error, kTwistTolerance * expected);
  // Pure twist does not bend or stretch a straight rod.
  double max_move = 0.0;
  for (int i = 0; i <= edges; ++i) max_move = std::max(max_move, displacement(net, s, i).norm());
  EXPECT_LT(max_move, kStraightnessTolerance);
}

}  // namespace
}  // namespace flagella
