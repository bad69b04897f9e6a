// The Euler-Bernoulli beam model (docs/model.md 6) and the DER rod model must agree at small motor
// speed, where the tails are only slightly bent and both models describe the same physics: RFT drag
// on straight-ish clamped tails (docs/model.md 2), Stokes head drag (docs/model.md 3.1) and the
// motor constraint. Compared at omega_T = 10 rpm for the granular designs 1 and 2
// (docs/model.md 8.1, 8.2): the tail tip deflection w(L), the propulsive force per tail F_p, and
// the spin rates.
//
// Rod tip deflection. The beam tail is planar: clamped at the plate at radius R_d, moving with
// velocity V = omega_t R_d along -x, deflected by w(y) along +x, i.e. opposite to its own motion
// and perpendicular to the plane spanned by the robot axis and the radial direction of the root.
// The rod counterpart is therefore measured in the co-rotating frame of the disc:
//   d = x_tip - x_root,  w = -d . vhat,  vhat = sign(omega_t) (ahat x rhat),
// with vhat the direction of motion of the root, rhat its radial unit vector and ahat the head
// axis. The rod also deflects within that plane (radially inward, ~7 % of w for design 1 and ~13 %
// for design 2 at 10 rpm): an element displaced by w behind its root moves with an extra radial
// velocity omega_t w, which the planar beam ignores, and its drag pulls the tail inward. That
// component is second order in w/R_d and has no beam counterpart, so it is only printed; it
// changes the magnitude of the tip's lateral displacement by less than 1 %.
//
// Rod propulsive force. At steady state the net tail force balances the Stokes drag of the head,
// so per tail F_p = C_t 6 pi mu a v / n_t with v the steady head speed. This is the net thrust
// including the tails' own axial drag, i.e. the beam's F_p with include_tail_axial_drag = true.
//
// Mesh. The rod's tail root spring is rigid (docs/model.md 8.1, glued tails), so the first tail
// edge cannot bend and the first flexible bending spring (second tail node) has the Voronoi domain
// [h/2, 3h/2]: the effective clamp sits about h/2 from the disc, a first-order error w ~ (L -
// h/2)^4, i.e. -2h/L = -7.4 % at the config's 27 edges (design 1) and -9.1 % at 22 edges (design
// 2). The comparison within 5 % therefore uses a 4x refined mesh, checks that the rod converges at
// first order, and checks that the Richardson extrapolation of the rod agrees with the beam more
// tightly. The config-mesh gap is printed for the record.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "flagella_sim/beam/euler_bernoulli_beam.h"
#include "flagella_sim/core/units.h"
#include "flagella_sim/simulation/simulation.h"
#include "flagella_sim/simulation/simulation_config.h"

namespace flagella {
namespace {

constexpr double kMotorRpm = 10.0;  // omega_T <= 10 rpm: w(L)/L ~ 2-3 %, slopes ~ 0.03

// ---- tolerances -----------------------------------------------------------------------------
// Beam vs rod on the finest mesh (4x the config's edges): the agreement required by the task.
// Measured on the finest mesh: design 1 w -2.0 %, F_p -1.7 %; design 2 w -3.3 %, F_p -2.6 %
// (mostly the remaining first-order clamp error); omega_h, omega_t within 0.6 %.
constexpr double kAgreementTolerance = 0.05;
// Beam vs the Richardson extrapolation 2 f(h/4) - f(h/2) of the rod, which removes the first-order
// mesh error. What remains are the 3D effects the planar beam omits (radial velocity of the
// deflected tail, O((w/R_d)^2) ~ 1-4 %) and the small-slope approximation (O(w'^2) ~ 1e-3).
// Measured: design 1 w -0.2 %, F_p +0.2 %; design 2 w -1.2 %, F_p -0.4 %.
constexpr double kExtrapolatedTolerance = 0.02;
// LB vs NLB beam at 10 rpm: the w'^2 terms are O(1e-3) (measured 1e-4).
constexpr double kLinearVsNonlinearTolerance = 0.005;
// First-order mesh convergence: successive differences f(h) - f(h/2) over f(h/2) - f(h/4) should
// be 2 (measured 1.97 for w and F_p of both designs).
constexpr double kMinConvergenceRatio = 1.6;
constexpr double kMaxConvergenceRatio = 2.5;
// Steady state: w varies by less than this (relative) across the summary window (measured 1e-8).
constexpr double kSteadyTolerance = 1e-3;
// The two tails of the n = 2 robot are related by the half-turn symmetry about the axis.
constexpr double kTailSymmetryTolerance = 1e-6;

struct DesignCase {
  std::string name;
  std::string config_file;
  double duration;         // [s]; the summary uses the second half
  std::vector<int> edges;  // config mesh, 2x, 4x
};

// First-mode tail relaxation eta_p L^4 / (1.875^4 EI): 2.2 s (design 1), 0.3 s (design 2); the
// deflection is steady to 1e-6 after ~12 s and ~5 s respectively.
const DesignCase kDesign1{"design 1", "granular_design1.yaml", 30.0, {27, 54, 108}};
const DesignCase kDesign2{"design 2", "granular_design2.yaml", 20.0, {22, 44, 88}};

struct RodResult {
  int edges = 0;
  double edge_length = 0.0;
  double tip_deflection = 0.0;     // w: along -(direction of motion of the root), mean of tails
  double radial_deflection = 0.0;  // in-plane, outward positive
  double steady_variation = 0.0;   // max |w(t) - w_mean| / w_mean over the window
  double tail_asymmetry = 0.0;     // |w_0 - w_1| / w_mean
  double omega_h = 0.0, omega_t = 0.0, speed = 0.0;
  double propulsive_force = 0.0;  // per tail, C_t 6 pi mu a v / n_t
  double wall_seconds = 0.0;
  beam::BeamDesign design;  // beam inputs taken from the same config
};

std::string configPath(const std::string& file) {
  return std::string(FLAGELLA_CONFIG_DIR) + "/" + file;
}

RodResult simulateRod(const DesignCase& dc, int edges) {
  SimulationConfig config = loadSimulationConfig(
      configPath(dc.config_file),
      {"robot.n_tails=2", "motor.omega_rpm=" + std::to_string(kMotorRpm),
       "simulation.duration=" + std::to_string(dc.duration), "simulation.steady_fraction=0.5"});
  config.editRobotGeometry<MultiTailGeometry>().tail_edges = edges;
  const auto start = std::chrono::steady_clock::now();
  Simulation sim(config);
  sim.setRecordNodes(true);
  sim.run(config.duration);
  RodResult r;
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const SummaryMetrics m = sim.summary();
  const RobotParts& parts = sim.network().parts;
  const double spin_sign = m.omega_t_signed >= 0.0 ? 1.0 : -1.0;

  std::vector<double> w_mean_per_sample, w_tail(parts.tail_nodes.size(), 0.0);
  double radial_sum = 0.0;
  int count = 0;
  for (const TrajectorySample& s : sim.trajectory()) {
    if (s.time < m.window_start || s.nodes.empty()) continue;
    const Vec3 x1 = s.nodes[parts.head_center_node], x2 = s.nodes[parts.joint_node];
    const Vec3 axis = (x2 - x1).normalized();
    double w_sum = 0.0;
    for (size_t k = 0; k < parts.tail_nodes.size(); ++k) {
      const Vec3 root = s.nodes[parts.tail_nodes[k].front()];
      const Vec3 tip = s.nodes[parts.tail_nodes[k].back()];
      Vec3 radial = (root - x2) - (root - x2).dot(axis) * axis;
      radial.normalize();
      const Vec3 motion = spin_sign * axis.cross(radial);
      const Vec3 d = tip - root;
      const double w = -d.dot(motion);
      w_sum += w;
      w_tail[k] += w;
      radial_sum += d.dot(radial);
    }
    w_mean_per_sample.push_back(w_sum / parts.tail_nodes.size());
    ++count;
  }
  EXPECT_GT(count, 10) << dc.name << ": too few samples in the steady window";
  const double n_tails = static_cast<double>(parts.tail_nodes.size());
  for (double& w : w_tail) w /= count;
  r.tip_deflection = (w_tail[0] + w_tail[1]) / 2.0;
  r.radial_deflection = radial_sum / (count * n_tails);
  for (double w : w_mean_per_sample)
    r.steady_variation =
        std::max(r.steady_variation, std::abs(w - r.tip_deflection) / r.tip_deflection);
  r.tail_asymmetry = std::abs(w_tail[0] - w_tail[1]) / r.tip_deflection;

  r.edges = edges;
  r.edge_length = config.robotGeometry<MultiTailGeometry>().tail_length / edges;
  r.omega_h = m.omega_h;
  r.omega_t = m.omega_t;
  r.speed = m.speed;

  beam::BeamDesign& d = r.design;
  d.n_tails = config.robotGeometry<MultiTailGeometry>().n_tails;
  d.tail_length = config.robotGeometry<MultiTailGeometry>().tail_length;
  d.tail_radius = config.robotGeometry<MultiTailGeometry>().tail_material.radius;
  d.youngs_modulus = config.robotGeometry<MultiTailGeometry>().tail_material.youngs_modulus;
  d.disc_radius = config.robotGeometry<MultiTailGeometry>().disc_radius;
  d.head_radius = sim.parameter("effects.stokes_head.head_radius");
  d.C_t = sim.parameter("effects.stokes_head.C_t");
  d.C_r = sim.parameter("effects.stokes_head.C_r");
  d.viscosity = sim.parameter("medium.viscosity");
  d.log_form =
      RftLogForm::kTwoLengthOverRadius;  // docs/model.md 8.1/8.2: ln(2L/r0) (Eq. 2.10 / 3.3)
  d.include_tail_axial_drag = true;      // the rod's head-drag balance is the net tail force
  r.propulsive_force = d.C_t * 6.0 * M_PI * d.viscosity * d.head_radius * r.speed / d.n_tails;
  return r;
}

// The three meshes of a design, simulated once per executable.
const std::vector<RodResult>& rodResults(const DesignCase& dc) {
  static std::map<std::string, std::vector<RodResult>> cache;
  auto it = cache.find(dc.name);
  if (it == cache.end()) {
    std::vector<RodResult> results;
    for (int edges : dc.edges) {
      results.push_back(simulateRod(dc, edges));
      std::printf("[beam vs rod] %s rod, %d edges: wall %.1f s\n", dc.name.c_str(), edges,
                  results.back().wall_seconds);
    }
    it = cache.emplace(dc.name, std::move(results)).first;
  }
  return it->second;
}

double relError(double value, double reference) {
  return (value - reference) / std::abs(reference);
}

void printRow(const std::string& what, double rod, double beam) {
  std::printf("[beam vs rod]   %-34s rod %.6e  beam %.6e  rel. diff %+.4f\n", what.c_str(), rod,
              beam, relError(rod, beam));
}

void checkDesign(const DesignCase& dc) {
  const std::vector<RodResult>& rods = rodResults(dc);
  ASSERT_EQ(rods.size(), 3u);
  const RodResult &coarse = rods[0], &mid = rods[1], &fine = rods[2];
  const beam::BeamDesign& design = fine.design;
  const double omega_T = units::rpmToRadPerSec(kMotorRpm);
  const beam::BeamSolution nlb =
      beam::solveBeamModel(design, omega_T, beam::BeamRegime::kNonlinear);
  const beam::BeamSolution lb = beam::solveBeamModel(design, omega_T, beam::BeamRegime::kLinear);
  ASSERT_TRUE(nlb.converged) << nlb.message;
  ASSERT_TRUE(lb.converged) << lb.message;

  const double w_extrapolated = 2.0 * fine.tip_deflection - mid.tip_deflection;
  const double fp_extrapolated = 2.0 * fine.propulsive_force - mid.propulsive_force;
  const double w_ratio =
      (mid.tip_deflection - coarse.tip_deflection) / (fine.tip_deflection - mid.tip_deflection);
  const double fp_ratio = (mid.propulsive_force - coarse.propulsive_force) /
                          (fine.propulsive_force - mid.propulsive_force);

  std::printf("[beam vs rod] %s at %.0f rpm (beam: NLB; LB w(L) %.6e, F_p %.6e)\n", dc.name.c_str(),
              kMotorRpm, lb.tip_deflection, lb.propulsive_force);
  for (const RodResult& r : rods) {
    const std::string mesh = std::to_string(r.edges) + " edges";
    printRow("w(L) " + mesh, r.tip_deflection, nlb.tip_deflection);
    printRow("F_p per tail " + mesh, r.propulsive_force, nlb.propulsive_force);
    printRow("omega_h " + mesh, r.omega_h, nlb.omega_h);
    printRow("omega_t " + mesh, r.omega_t, nlb.omega_t);
    printRow("speed " + mesh, r.speed, nlb.speed);
    std::printf(
        "[beam vs rod]   %-34s radial/w %+.4f, steady variation %.1e, tail asymmetry %.1e\n",
        ("in-plane deflection " + mesh).c_str(), r.radial_deflection / r.tip_deflection,
        r.steady_variation, r.tail_asymmetry);
  }
  printRow("w(L) Richardson extrapolated", w_extrapolated, nlb.tip_deflection);
  printRow("F_p Richardson extrapolated", fp_extrapolated, nlb.propulsive_force);
  const double h = coarse.edge_length, L = design.tail_length;
  std::printf(
      "[beam vs rod]   mesh ratios w %.3f, F_p %.3f; config-mesh w / extrapolated %.5f vs "
      "clamp-offset estimate (1 - h/2L)^4 = %.5f\n",
      w_ratio, fp_ratio, coarse.tip_deflection / w_extrapolated, std::pow(1.0 - 0.5 * h / L, 4));

  // Both beam regimes agree at this small deflection.
  EXPECT_NEAR(lb.tip_deflection, nlb.tip_deflection,
              kLinearVsNonlinearTolerance * nlb.tip_deflection);
  EXPECT_NEAR(lb.propulsive_force, nlb.propulsive_force,
              kLinearVsNonlinearTolerance * nlb.propulsive_force);

  for (const RodResult& r : rods) {
    // Steady, symmetric, and the tails trail behind their own motion (w > 0 like the beam's).
    EXPECT_GT(r.tip_deflection, 0.0) << r.edges << " edges";
    EXPECT_LT(r.steady_variation, kSteadyTolerance) << r.edges << " edges";
    EXPECT_LT(r.tail_asymmetry, kTailSymmetryTolerance) << r.edges << " edges";
    EXPECT_GT(r.speed, 0.0) << r.edges << " edges";
  }
  // Finest mesh within 5 % of the beam model.
  EXPECT_LT(std::abs(relError(fine.tip_deflection, nlb.tip_deflection)), kAgreementTolerance);
  EXPECT_LT(std::abs(relError(fine.propulsive_force, nlb.propulsive_force)), kAgreementTolerance);
  EXPECT_LT(std::abs(relError(fine.omega_h, nlb.omega_h)), kAgreementTolerance);
  EXPECT_LT(std::abs(relError(fine.omega_t, nlb.omega_t)), kAgreementTolerance);
  EXPECT_LT(std::abs(relError(fine.tip_deflection, lb.tip_deflection)), kAgreementTolerance);
  EXPECT_LT(std::abs(relError(fine.propulsive_force, lb.propulsive_force)), kAgreementTolerance);
  // First-order convergence of the rod, and its limit agrees with the beam more closely.
  EXPECT_GT(w_ratio, kMinConvergenceRatio);
  EXPECT_LT(w_ratio, kMaxConvergenceRatio);
  EXPECT_GT(fp_ratio, kMinConvergenceRatio);
  EXPECT_LT(fp_ratio, kMaxConvergenceRatio);
  EXPECT_LT(std::abs(relError(w_extrapolated, nlb.tip_deflection)), kExtrapolatedTolerance);
  EXPECT_LT(std::abs(relError(fp_extrapolated, nlb.propulsive_force)), kExtrapolatedTolerance);
}

TEST(BeamVsRod, Design1AtTenRpm) { checkDesign(kDesign1); }

TEST(BeamVsRod, Design2AtTenRpm) { checkDesign(kDesign2); }

}  // namespace
}  // namespace flagella
