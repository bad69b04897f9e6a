// The Newton iteration path (docs/model.md 1.10): the second-order predictor and chord updates
// change how a step is solved, not what it converges to. Each robot is run with the default path
// and with plain Newton from q(t_k) with a fresh Jacobian for every update (no predictor, no
// chord steps); the converged steps satisfy the same residual test, so their outputs must agree
// to within the effect of that tolerance, while the default path needs fewer Jacobians.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "flagella_sim/simulation/simulation.h"
#include "flagella_sim/solver/solver_failure.h"
#include "flagella_sim/solver/step_profile.h"

namespace flagella {
namespace {

const std::string kConfigDir = FLAGELLA_CONFIG_DIR;

struct PathRun {
  TrajectorySample last;
  StepProfile profile;
  long newton_iterations = 0;
  long subdivided_steps = 0;
  long damped_retries = 0;
  double max_speed = 0.0;  // largest head speed over the run [m/s]
};

PathRun runPath(const std::string& config, std::vector<std::string> overrides, double seconds,
                bool plain_newton) {
  if (plain_newton) {
    overrides.push_back("solver.extrapolate_initial_guess=false");
    overrides.push_back("solver.jacobian_reuse=0");
  }
  Simulation sim(loadSimulationConfig(kConfigDir + "/" + config, overrides));
  PathRun out;
  sim.setProfile(&out.profile);
  const long steps = std::lround(seconds / sim.config().dt);
  for (long k = 0; k < steps; ++k) {
    const StepReport report = sim.step();
    out.newton_iterations += report.newton_iterations;
    if (report.substeps > 1) ++out.subdivided_steps;
    out.damped_retries += report.damped_retries;
    out.max_speed = std::max(out.max_speed, sim.sample().head_velocity.norm());
  }
  sim.setProfile(nullptr);
  out.last = sim.sample();
  return out;
}

// The interface robot's discovery config (dt = 0.05 s), as flagella_discovery_bench runs it.
const std::string kInterfaceDiscoveryConfig = "identification/interface_4tails_coarse.yaml";

// `overrides` with `setting` added.
std::vector<std::string> with(std::vector<std::string> overrides, const std::string& setting) {
  overrides.push_back(setting);
  return overrides;
}

void expectSameAnswerWithFewerJacobians(const std::string& config,
                                        const std::vector<std::string>& overrides, double seconds) {
  SCOPED_TRACE(config);
  const PathRun fast = runPath(config, overrides, seconds, false);
  const PathRun plain = runPath(config, overrides, seconds, true);
  // The same trajectory: head position within 1e-4 of the distance the head could have covered,
  // head axis within 1e-4 rad (the tolerance 1e-4 moves summaries by about 1e-5, section 1.10).
  const double travel = plain.max_speed * seconds;
  ASSERT_GT(travel, 0.0);
  EXPECT_LT((fast.last.head_position - plain.last.head_position).norm(), 1e-4 * travel);
  EXPECT_LT((fast.last.head_axis - plain.last.head_axis).norm(), 1e-4);
  EXPECT_LT((fast.last.head_velocity - plain.last.head_velocity).norm(), 1e-3 * plain.max_speed);
  // Fewer Jacobians and factorizations; every step's first update has a fresh one.
  EXPECT_EQ(fast.profile.steps, plain.profile.steps);
  EXPECT_LT(fast.profile.jacobians, plain.profile.jacobians);
  EXPECT_LT(fast.profile.factorizations, plain.profile.factorizations);
  EXPECT_GE(fast.profile.factorizations, fast.profile.steps);
  EXPECT_LE(fast.newton_iterations, plain.newton_iterations);
  ::testing::Test::RecordProperty(
      "jacobians_per_step_default",
      std::to_string(double(fast.profile.jacobians) / fast.profile.steps));
  ::testing::Test::RecordProperty(
      "jacobians_per_step_plain",
      std::to_string(double(plain.profile.jacobians) / plain.profile.steps));
}

TEST(NewtonIterationPath, Design1SameAnswerFewerJacobians) {
  expectSameAnswerWithFewerJacobians("granular_design1.yaml",
                                     {"robot.n_tails=3", "motor.omega_rpm=100"}, 3.0);
}

TEST(NewtonIterationPath, InterfaceRobotSameAnswerFewerJacobians) {
  expectSameAnswerWithFewerJacobians("interface_robot.yaml", {"robot.n_tails=2"}, 3.0);
}

// The interface robot's discovery config (dt = 0.05 s) at the discovery series' first motor rate
// (120 rpm), where head and tails turn by about 21 and 15 deg per step, at the fits' tolerance
// (1e-7): the rotating predictor (docs/model.md 1.10) and the linear one converge to the same
// steps, the rotating one in fewer Newton iterations.
TEST(NewtonIterationPath, CoarseInterfaceRobotRotatingPredictorSameAnswerFewerIterations) {
  const std::vector<std::string> overrides = {"motor.omega_rpm=120",
                                              "solver.residual_tolerance=1e-7"};
  const double seconds = 5.0;
  const PathRun rotating = runPath(kInterfaceDiscoveryConfig,
                                   with(overrides, "solver.predictor=rotating"), seconds, false);
  const PathRun linear = runPath(kInterfaceDiscoveryConfig,
                                 with(overrides, "solver.predictor=linear"), seconds, false);
  const double travel = linear.max_speed * seconds;
  ASSERT_GT(travel, 0.0);
  EXPECT_LT((rotating.last.head_position - linear.last.head_position).norm(), 1e-4 * travel);
  EXPECT_LT((rotating.last.head_axis - linear.last.head_axis).norm(), 1e-4);
  EXPECT_LT((rotating.last.head_velocity - linear.last.head_velocity).norm(),
            1e-3 * linear.max_speed);
  EXPECT_EQ(rotating.profile.steps, linear.profile.steps);
  EXPECT_EQ(rotating.subdivided_steps, linear.subdivided_steps);
  EXPECT_LT(rotating.newton_iterations, linear.newton_iterations);
  ::testing::Test::RecordProperty("newton_iterations_rotating",
                                  std::to_string(rotating.newton_iterations));
  ::testing::Test::RecordProperty("newton_iterations_linear",
                                  std::to_string(linear.newton_iterations));
}

// The interface robot's discovery config at the discovery series' fastest motor rate with the
// strong lateral force of the discovery case strong_lateral_4_tails (C_yr 0.3), at the fits'
// tolerance: plain Newton alternates between a large and a falling residual (the second update
// raises it about 1000-fold, the third brings it below the first) and converges in about 12
// updates. Judged over two updates (the solver's default) it is taken for stagnating and handed to
// the damped retry, which crawls, and the step is subdivided; judged over four
// (solver.stagnation_updates, which this config sets since 2026-12-07) no step is, and the run is
// the one without the damped retry at all, update for update (docs/model.md 1.10).
TEST(NewtonIterationPath, FourUpdateStagnationWindowLetsAnAlternatingNewtonConverge) {
  const std::vector<std::string> overrides = {"motor.omega_rpm=240",
                                              "solver.residual_tolerance=1e-7",
                                              "effects.interface_lateral_force.C_yr=0.3"};
  const double seconds = 10.0;
  auto run = [&](const std::string& setting) {
    return runPath(kInterfaceDiscoveryConfig, with(overrides, setting), seconds, false);
  };
  const PathRun four = run("solver.stagnation_updates=4");
  const PathRun two = run("solver.stagnation_updates=2");
  const PathRun undamped = run("solver.damped_retry=false");
  EXPECT_EQ(four.subdivided_steps, 0);
  EXPECT_EQ(four.damped_retries, 0);
  EXPECT_GT(two.subdivided_steps, 0);
  EXPECT_EQ(undamped.subdivided_steps, 0);
  EXPECT_EQ(four.newton_iterations, undamped.newton_iterations);
  EXPECT_EQ(four.last.head_position, undamped.last.head_position);
  EXPECT_LT(four.newton_iterations, two.newton_iterations);
  ::testing::Test::RecordProperty("subdivided_steps_window_2",
                                  std::to_string(two.subdivided_steps));
}

// A two-cycle is still caught with the four-update window: granular jamming at a stop (the case
// the damped retry exists for, docs/model.md 1.10) on the same robot runs on through the damped
// retry, where the run without it stops by a solver failure.
TEST(NewtonIterationPath, FourUpdateStagnationWindowStillHandsATwoCycleToTheDampedRetry) {
  const std::vector<std::string> jamming = {"motor.omega_rpm=240", "solver.residual_tolerance=1e-7",
                                            "effects.granular_jamming.stiffness=100",
                                            "effects.granular_jamming.release_force=0.01"};
  const double seconds = 1.5;
  const PathRun four = runPath(kInterfaceDiscoveryConfig,
                               with(jamming, "solver.stagnation_updates=4"), seconds, false);
  EXPECT_GT(four.damped_retries, 0);
  EXPECT_THROW(runPath(kInterfaceDiscoveryConfig, with(jamming, "solver.damped_retry=false"),
                       seconds, false),
               SolverFailure);
}

TEST(NewtonIterationPath, ProfileAccountsForTheStep) {
  // The parts of the profile are disjoint and lie inside the steps' total.
  const PathRun run = runPath("granular_design1.yaml", {"robot.n_tails=2"}, 0.5, false);
  const StepProfile& p = run.profile;
  EXPECT_GT(p.steps, 0);
  for (double part :
       {p.frames, p.elastic, p.effects, p.assembly, p.factorization, p.solve, p.convergence})
    EXPECT_GT(part, 0.0);
  EXPECT_GE(p.other(), 0.0);
  EXPECT_EQ(p.updates, run.newton_iterations);
  EXPECT_GE(p.residuals, p.updates + p.steps);  // at least one more evaluation than updates
  EXPECT_GE(p.jacobians, p.factorizations);
  // The same time cut by evaluation: both kinds happened, and they lie inside the steps' total
  // together with the frames (which they exclude).
  EXPECT_GT(p.residual_evaluations, 0.0);
  EXPECT_GT(p.jacobian_evaluations, 0.0);
  EXPECT_LE(p.residual_evaluations + p.jacobian_evaluations + p.frames, p.total);
}

}  // namespace
}  // namespace flagella
