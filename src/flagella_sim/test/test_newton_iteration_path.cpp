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
#include "flagella_sim/solver/step_profile.h"

namespace flagella {
namespace {

const std::string kConfigDir = FLAGELLA_CONFIG_DIR;

struct PathRun {
  TrajectorySample last;
  StepProfile profile;
  long newton_iterations = 0;
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
    out.newton_iterations += sim.step().newton_iterations;
    out.max_speed = std::max(out.max_speed, sim.sample().head_velocity.norm());
  }
  sim.setProfile(nullptr);
  out.last = sim.sample();
  return out;
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
