// Tests of the Euler–Bernoulli beam model (docs/model.md 6) against independent truth: the
// closed-form LB solution and its analytic deflection profile, the balances recomputed from the
// formulas of docs/model.md, an independent Picard/trapezoid solve of the nonlinear tail BVP, and
// mesh refinement.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "flagella_sim/beam/euler_bernoulli_beam.h"
#include "flagella_sim/core/units.h"

namespace flagella::beam {
namespace {

constexpr double kClosedFormTolerance = 1e-6;       // numeric LB vs closed form (relative)
constexpr double kProfileTolerance = 1e-9;          // RK4 is exact for the quartic LB profile
constexpr double kBalanceTolerance = 1e-12;         // closed-form balances (rounding only)
constexpr double kNumericBalanceTolerance = 1e-8;   // balances of the numeric solution
constexpr double kSmallDeflectionAgreement = 0.01;  // NLB vs LB at 1 rpm
constexpr double kMeshChangeTolerance = 1e-5;       // tip change when doubling the resolution
constexpr double kReferenceTolerance = 1e-6;        // shooting vs Picard/trapezoid reference
constexpr int kReferenceNodes = 20000;              // trapezoid nodes of the reference solve
constexpr double kPicardTolerance = 1e-14;
constexpr int kMaxPicardIterations = 500;

double rpm(double value) { return units::rpmToRadPerSec(value); }

// Design 1 of docs/model.md 8.1 with the beam inputs of docs/model.md 6.
BeamDesign design1() {
  BeamDesign d;
  d.n_tails = 2;
  d.tail_length = 0.111;
  d.tail_radius = 3.2e-3;
  d.youngs_modulus = 1.2e6;
  d.disc_radius = 0.02;
  d.head_radius = 0.02;
  d.C_t = 2.420;
  d.C_r = 0.039;
  d.viscosity = 6.828;
  d.log_form = RftLogForm::kTwoLengthOverRadius;
  return d;
}

// Independent drag coefficients of docs/model.md 2 with the ln(2L/r0) form, and EI of 6.
struct Coefficients {
  double eta_t, eta_p, EI;
};
Coefficients coefficients(const BeamDesign& d) {
  const double log_term = std::log(2.0 * d.tail_length / d.tail_radius);
  return {2.0 * M_PI * d.viscosity / (log_term - 0.5), 4.0 * M_PI * d.viscosity / (log_term + 0.5),
          d.youngs_modulus * M_PI * std::pow(d.tail_radius, 4) / 4.0};
}

void expectRelNear(double actual, double expected, double tolerance, const std::string& what) {
  EXPECT_NEAR(actual, expected, tolerance * std::abs(expected)) << what;
}

void expectSolutionsAgree(const BeamSolution& a, const BeamSolution& b, double tolerance,
                          const std::string& label) {
  expectRelNear(a.omega_t, b.omega_t, tolerance, label + " omega_t");
  expectRelNear(a.omega_h, b.omega_h, tolerance, label + " omega_h");
  expectRelNear(a.speed, b.speed, tolerance, label + " speed");
  expectRelNear(a.tip_deflection, b.tip_deflection, tolerance, label + " tip deflection");
}

// ---- 1. numeric LB (shooting BVP + root finds) vs closed form --------------------------------

TEST(BeamModel, LinearNumericMatchesClosedForm) {
  for (const bool axial_drag : {true, false}) {
    BeamDesign d = design1();
    d.include_tail_axial_drag = axial_drag;
    for (const double omega_rpm : {1.0, 10.0, 100.0, 250.0}) {
      const BeamSolution numeric = solveBeamModel(d, rpm(omega_rpm), BeamRegime::kLinear);
      const BeamSolution closed = linearBeamClosedForm(d, rpm(omega_rpm));
      ASSERT_TRUE(numeric.converged) << numeric.message;
      const std::string label =
          std::to_string(omega_rpm) + " rpm, axial " + std::to_string(axial_drag);
      expectSolutionsAgree(numeric, closed, kClosedFormTolerance, label);
      expectRelNear(numeric.propulsive_force, closed.propulsive_force, kClosedFormTolerance,
                    label + " F_p");
      expectRelNear(numeric.lateral_force, closed.lateral_force, kClosedFormTolerance,
                    label + " F_x");
    }
  }
}

TEST(BeamModel, LinearProfileMatchesAnalyticDeflection) {
  const BeamDesign d = design1();
  const Coefficients c = coefficients(d);
  const double omega_t = rpm(5.0), v_h = 1e-3, L = d.tail_length;
  const FlagellumLoads loads = solveFlagellum(d, omega_t, v_h, BeamRegime::kLinear);
  ASSERT_TRUE(loads.converged) << loads.message;
  ASSERT_EQ(loads.y.size(), loads.w.size());
  const double p = c.eta_p * omega_t * d.disc_radius;  // docs/model.md 6 LB load
  const double tip = p * std::pow(L, 4) / (8.0 * c.EI);
  for (size_t i = 0; i < loads.y.size(); ++i) {
    const double y = loads.y[i];
    const double w = p * y * y * (6.0 * L * L - 4.0 * L * y + y * y) / (24.0 * c.EI);
    EXPECT_NEAR(loads.w[i], w, kProfileTolerance * tip) << "y = " << y;
  }
  EXPECT_NEAR(loads.y.back(), L, kProfileTolerance * L);
  expectRelNear(loads.tip_deflection, tip, kProfileTolerance, "w(L)");
  expectRelNear(loads.lateral_force, p * L, kProfileTolerance, "F_x");
  const double thrust = (c.eta_p - c.eta_t) * omega_t * d.disc_radius * tip - c.eta_t * v_h * L;
  expectRelNear(loads.propulsive_force, thrust, kProfileTolerance, "F_p");
}

// ---- 2. closed form satisfies the balances ----------------------------------------------------

void expectClosedFormBalances(const BeamDesign& d, double omega_T) {
  const Coefficients c = coefficients(d);
  const BeamSolution s = linearBeamClosedForm(d, omega_T);
  const double n = d.n_tails, a = d.head_radius, mu = d.viscosity, L = d.tail_length;
  const double V = s.omega_t * d.disc_radius;
  // Tail forces recomputed from the returned rates (docs/model.md 6, LB).
  const double tip = c.eta_p * V * std::pow(L, 4) / (8.0 * c.EI);
  const double F_x = c.eta_p * V * L;
  const double F_p =
      (c.eta_p - c.eta_t) * V * tip - (d.include_tail_axial_drag ? c.eta_t * s.speed * L : 0.0);
  expectRelNear(s.tip_deflection, tip, kBalanceTolerance, "w(L)");
  expectRelNear(s.relative_tip_deflection, tip / L, kBalanceTolerance, "w(L)/L");
  expectRelNear(s.lateral_force, F_x, kBalanceTolerance, "F_x");
  expectRelNear(s.propulsive_force, F_p, kBalanceTolerance, "F_p");
  expectRelNear(n * F_x * d.disc_radius, d.C_r * 8.0 * M_PI * mu * a * a * a * s.omega_h,
                kBalanceTolerance, "torque balance");
  expectRelNear(n * F_p, d.C_t * 6.0 * M_PI * mu * a * s.speed, kBalanceTolerance, "force balance");
  expectRelNear(s.omega_h + s.omega_t, omega_T, kBalanceTolerance, "motor");
}

TEST(BeamModel, ClosedFormSatisfiesBalances) {
  BeamDesign d = design1();
  for (const double omega_rpm : {10.0, 100.0, 250.0}) expectClosedFormBalances(d, rpm(omega_rpm));
  d.include_tail_axial_drag = false;
  for (const double omega_rpm : {10.0, 100.0, 250.0}) expectClosedFormBalances(d, rpm(omega_rpm));
  d.n_tails = 3;
  expectClosedFormBalances(d, rpm(50.0));
}

TEST(BeamModel, ZeroMotorSpeedGivesRest) {
  for (const BeamRegime regime :
       {BeamRegime::kLinear, BeamRegime::kNonlinear, BeamRegime::kNonlinearWithoutHead}) {
    const BeamSolution s = solveBeamModel(design1(), 0.0, regime);
    EXPECT_TRUE(s.converged);
    EXPECT_EQ(s.omega_t, 0.0);
    EXPECT_EQ(s.speed, 0.0);
    EXPECT_EQ(s.tip_deflection, 0.0);
  }
}

// ---- 3. nonlinear regime ----------------------------------------------------------------------

TEST(BeamModel, NonlinearAgreesWithLinearAtSmallSpeed) {
  BeamDesign d = design1();
  const BeamSolution lb = solveBeamModel(d, rpm(1.0), BeamRegime::kLinear);
  const BeamSolution nlb = solveBeamModel(d, rpm(1.0), BeamRegime::kNonlinear);
  const BeamSolution nlb_no_head = solveBeamModel(d, rpm(1.0), BeamRegime::kNonlinearWithoutHead);
  ASSERT_TRUE(nlb.converged) << nlb.message;
  ASSERT_TRUE(nlb_no_head.converged) << nlb_no_head.message;
  expectSolutionsAgree(nlb, lb, kSmallDeflectionAgreement, "NLB vs LB");
  // With v_h = 0 inside q the tail feels no axial drag: the small-slope limit is the LB solution
  // without the eta_t v_h L term.
  d.include_tail_axial_drag = false;
  const BeamSolution lb_no_axial = linearBeamClosedForm(d, rpm(1.0));
  expectSolutionsAgree(nlb_no_head, lb_no_axial, kSmallDeflectionAgreement, "NLB w/o head vs LB");
}

TEST(BeamModel, NonlinearDeflectsLessThanLinearAtLargeSpeed) {
  const BeamDesign d = design1();
  const BeamSolution lb = solveBeamModel(d, rpm(250.0), BeamRegime::kLinear);
  const BeamSolution nlb = solveBeamModel(d, rpm(250.0), BeamRegime::kNonlinear);
  ASSERT_TRUE(lb.converged) << lb.message;
  ASSERT_TRUE(nlb.converged) << nlb.message;
  EXPECT_LT(nlb.tip_deflection, lb.tip_deflection);
  EXPECT_LT(nlb.relative_tip_deflection, lb.relative_tip_deflection);
  EXPECT_GT(std::abs(nlb.tip_deflection - lb.tip_deflection),
            kSmallDeflectionAgreement * lb.tip_deflection);
}

// The numeric NLB solution must satisfy the three balances of docs/model.md 6.
TEST(BeamModel, NonlinearSolutionSatisfiesBalances) {
  const BeamDesign d = design1();
  const double n = d.n_tails, a = d.head_radius, mu = d.viscosity;
  for (const BeamRegime regime : {BeamRegime::kNonlinear, BeamRegime::kNonlinearWithoutHead}) {
    const BeamSolution s = solveBeamModel(d, rpm(150.0), regime);
    ASSERT_TRUE(s.converged) << s.message;
    expectRelNear(n * s.lateral_force * d.disc_radius,
                  d.C_r * 8.0 * M_PI * mu * a * a * a * s.omega_h, kNumericBalanceTolerance,
                  toString(regime) + " torque balance");
    expectRelNear(n * s.propulsive_force, d.C_t * 6.0 * M_PI * mu * a * s.speed,
                  kNumericBalanceTolerance, toString(regime) + " force balance");
    expectRelNear(s.omega_h + s.omega_t, s.omega_T, kNumericBalanceTolerance, "motor");
    EXPECT_GT(s.speed, 0.0);
  }
}

// Independent solve of EI w'''' = p(w') (docs/model.md 6): Picard iteration on the integral form
// EI w''(y) = int_y^L int_s^L p, with cumulative trapezoid quadrature on a fine grid.
struct ReferenceTail {
  double tip, F_x, F_p;
};

std::vector<double> integrateFromStart(const std::vector<double>& f, double h) {
  std::vector<double> out(f.size(), 0.0);
  for (size_t i = 1; i < f.size(); ++i) out[i] = out[i - 1] + 0.5 * h * (f[i - 1] + f[i]);
  return out;
}

std::vector<double> integrateToEnd(const std::vector<double>& f, double h) {
  std::vector<double> out(f.size(), 0.0);
  for (size_t i = f.size() - 1; i-- > 0;) out[i] = out[i + 1] + 0.5 * h * (f[i] + f[i + 1]);
  return out;
}

ReferenceTail picardReference(const BeamDesign& d, double omega_t, double v_p, double v_q) {
  const Coefficients c = coefficients(d);
  const double V = omega_t * d.disc_radius, h = d.tail_length / kReferenceNodes;
  auto p = [&](double s) {
    return c.eta_p * V + (c.eta_t - c.eta_p) * (V * s * s + v_p * s) / (1.0 + s * s);
  };
  auto q = [&](double s) {
    return (c.eta_p - c.eta_t) * (V * s + v_q) / (1.0 + s * s) - c.eta_p * v_q;
  };
  auto sample = [](const std::vector<double>& u, const std::function<double(double)>& f) {
    std::vector<double> out(u.size());
    for (size_t i = 0; i < u.size(); ++i) out[i] = f(u[i]);
    return out;
  };
  std::vector<double> slope(kReferenceNodes + 1, 0.0);
  for (int it = 0; it < kMaxPicardIterations; ++it) {
    const std::vector<double> moment = integrateToEnd(integrateToEnd(sample(slope, p), h), h);
    std::vector<double> next = integrateFromStart(moment, h);
    double change = 0.0, size = 0.0;
    for (size_t i = 0; i < next.size(); ++i) {
      next[i] /= c.EI;
      change = std::max(change, std::abs(next[i] - slope[i]));
      size = std::max(size, std::abs(next[i]));
    }
    slope = next;
    if (change <= kPicardTolerance * size) break;
  }
  return {integrateFromStart(slope, h).back(), integrateFromStart(sample(slope, p), h).back(),
          integrateFromStart(sample(slope, q), h).back()};
}

TEST(BeamModel, NonlinearTailMatchesIndependentReference) {
  const BeamDesign d = design1();
  const BeamSolution s = solveBeamModel(d, rpm(250.0), BeamRegime::kNonlinear);
  ASSERT_TRUE(s.converged) << s.message;
  const FlagellumLoads nlb = solveFlagellum(d, s.omega_t, s.speed, BeamRegime::kNonlinear);
  const FlagellumLoads no_head =
      solveFlagellum(d, s.omega_t, s.speed, BeamRegime::kNonlinearWithoutHead);
  const ReferenceTail ref = picardReference(d, s.omega_t, s.speed, s.speed);
  const ReferenceTail ref_no_head = picardReference(d, s.omega_t, 0.0, 0.0);
  expectRelNear(nlb.tip_deflection, ref.tip, kReferenceTolerance, "NLB w(L)");
  expectRelNear(nlb.lateral_force, ref.F_x, kReferenceTolerance, "NLB F_x");
  expectRelNear(nlb.propulsive_force, ref.F_p, kReferenceTolerance, "NLB F_p");
  expectRelNear(no_head.tip_deflection, ref_no_head.tip, kReferenceTolerance, "w/o head w(L)");
  expectRelNear(no_head.lateral_force, ref_no_head.F_x, kReferenceTolerance, "w/o head F_x");
  expectRelNear(no_head.propulsive_force, ref_no_head.F_p, kReferenceTolerance, "w/o head F_p");
  expectRelNear(nlb.tip_deflection, s.tip_deflection, kReferenceTolerance, "solution w(L)");
}

TEST(BeamModel, WithoutHeadIgnoresHeadSpeedInLoads) {
  const BeamDesign d = design1();
  const FlagellumLoads still = solveFlagellum(d, 1.0, 0.0, BeamRegime::kNonlinearWithoutHead);
  const FlagellumLoads moving = solveFlagellum(d, 1.0, 0.01, BeamRegime::kNonlinearWithoutHead);
  const FlagellumLoads full = solveFlagellum(d, 1.0, 0.0, BeamRegime::kNonlinear);
  EXPECT_EQ(still.tip_deflection, moving.tip_deflection);
  EXPECT_EQ(still.propulsive_force, moving.propulsive_force);
  EXPECT_EQ(still.tip_deflection, full.tip_deflection);
}

TEST(BeamModel, TailAxialDragSwitchDropsOnlyThrustTerm) {
  BeamDesign d = design1();
  d.include_tail_axial_drag = false;
  const FlagellumLoads moving = solveFlagellum(d, 1.0, 0.01, BeamRegime::kLinear);
  const FlagellumLoads still = solveFlagellum(d, 1.0, 0.0, BeamRegime::kLinear);
  EXPECT_EQ(moving.propulsive_force, still.propulsive_force);
  const Coefficients c = coefficients(d);
  const double V = d.disc_radius;
  expectRelNear(moving.propulsive_force, (c.eta_p - c.eta_t) * V * moving.tip_deflection,
                kProfileTolerance, "F_p without axial drag");
}

// ---- 4. resolution convergence ----------------------------------------------------------------

TEST(BeamModel, NonlinearSolverConvergesUnderMeshRefinement) {
  const BeamDesign d = design1();
  BeamSolverOptions coarse, fine;
  fine.num_steps = 2 * coarse.num_steps;
  const BeamSolution a = solveBeamModel(d, rpm(250.0), BeamRegime::kNonlinear, coarse);
  const BeamSolution b = solveBeamModel(d, rpm(250.0), BeamRegime::kNonlinear, fine);
  ASSERT_TRUE(a.converged && b.converged);
  expectRelNear(a.tip_deflection, b.tip_deflection, kMeshChangeTolerance, "tip, 2x steps");
  expectRelNear(a.speed, b.speed, kMeshChangeTolerance, "speed, 2x steps");

  // Fourth-order convergence of the RK4 shooting on deliberately coarse meshes.
  constexpr int kCoarseSteps = 8;
  constexpr double kMinObservedOrder = 3.5;
  double tips[3];
  for (int level = 0; level < 3; ++level) {
    BeamSolverOptions options;
    options.num_steps = kCoarseSteps << level;
    tips[level] =
        solveFlagellum(d, b.omega_t, b.speed, BeamRegime::kNonlinear, options).tip_deflection;
  }
  const double order = std::log2((tips[0] - tips[1]) / (tips[1] - tips[2]));
  EXPECT_GT(order, kMinObservedOrder);
}

// ---- 5. input validation and failure reporting ------------------------------------------------

void expectInvalid(const std::function<void()>& call, const std::string& field) {
  try {
    call();
    ADD_FAILURE() << "no exception for " << field;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
  }
}

void expectInvalidDesign(const std::function<void(BeamDesign&)>& mutate, const std::string& field) {
  BeamDesign d = design1();
  mutate(d);
  expectInvalid([&] { solveBeamModel(d, rpm(10.0), BeamRegime::kNonlinear); }, field);
  expectInvalid([&] { linearBeamClosedForm(d, rpm(10.0)); }, field);
  expectInvalid([&] { solveFlagellum(d, 1.0, 0.0, BeamRegime::kLinear); }, field);
}

TEST(BeamModel, InvalidInputsThrowNamingTheField) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  expectInvalidDesign([](BeamDesign& d) { d.n_tails = 0; }, "n_tails");
  expectInvalidDesign([](BeamDesign& d) { d.tail_length = -0.1; }, "tail_length");
  expectInvalidDesign([](BeamDesign& d) { d.tail_radius = 0.0; }, "tail_radius");
  expectInvalidDesign([](BeamDesign& d) { d.tail_radius = 2.0 * d.tail_length; }, "tail_radius");
  expectInvalidDesign([=](BeamDesign& d) { d.youngs_modulus = nan; }, "youngs_modulus");
  expectInvalidDesign([](BeamDesign& d) { d.disc_radius = 0.0; }, "disc_radius");
  expectInvalidDesign([](BeamDesign& d) { d.head_radius = -0.02; }, "head_radius");
  expectInvalidDesign([](BeamDesign& d) { d.C_t = 0.0; }, "C_t");
  expectInvalidDesign([](BeamDesign& d) { d.C_r = -1.0; }, "C_r");
  expectInvalidDesign([](BeamDesign& d) { d.viscosity = 0.0; }, "viscosity");

  const BeamDesign d = design1();
  expectInvalid([&] { solveBeamModel(d, -1.0, BeamRegime::kLinear); }, "omega_T");
  expectInvalid([&] { linearBeamClosedForm(d, nan); }, "omega_T");
  expectInvalid([&] { solveFlagellum(d, -1.0, 0.0, BeamRegime::kLinear); }, "omega_t");
  expectInvalid([&] { solveFlagellum(d, 1.0, INFINITY, BeamRegime::kLinear); }, "v_h");
  BeamSolverOptions options;
  options.num_steps = 1;
  expectInvalid([&] { solveBeamModel(d, 1.0, BeamRegime::kLinear, options); }, "num_steps");
  expectInvalid([&] { solveBeamModel(d, 1.0, static_cast<BeamRegime>(7)); }, "regime");
}

TEST(BeamModel, NonConvergenceIsReportedWithoutNaN) {
  BeamSolverOptions options;
  options.max_bvp_iterations = 1;
  const BeamSolution s = solveBeamModel(design1(), rpm(250.0), BeamRegime::kNonlinear, options);
  EXPECT_FALSE(s.converged);
  EXPECT_FALSE(s.message.empty());
  for (const double value : {s.omega_t, s.omega_h, s.speed, s.tip_deflection, s.propulsive_force,
                             s.lateral_force, s.relative_tip_deflection})
    EXPECT_TRUE(std::isfinite(value));
}

// Prints the design-1 numbers quoted in the report (no assertions beyond convergence).
TEST(BeamModel, Design1Table) {
  const BeamDesign d = design1();
  for (const double omega_rpm : {10.0, 100.0, 250.0}) {
    for (const BeamRegime regime :
         {BeamRegime::kLinear, BeamRegime::kNonlinear, BeamRegime::kNonlinearWithoutHead}) {
      const BeamSolution s = solveBeamModel(d, rpm(omega_rpm), regime);
      ASSERT_TRUE(s.converged) << s.message;
      std::printf("%6.1f rpm %-13s omega_h %.6e  omega_t %.6e  v_h %.6e  w(L)/L %.6e  (%d it)\n",
                  omega_rpm, toString(regime).c_str(), s.omega_h, s.omega_t, s.speed,
                  s.relative_tip_deflection, s.iterations);
    }
  }
}

}  // namespace
}  // namespace flagella::beam
