// Benchmark program for the helical robot with RSS hydrodynamics (docs/model.md 4, 8.4): real-time
// factor below the buckling threshold and buckled, with the shipped solver and with the exact one
// (RSS matrix rebuilt and Jacobian factored at every step: effects.rss.reuse_tolerance = 0,
// solver.krylov_iterations = 0), a per-part breakdown of one step's cost, the growth of the cost
// with node count, and the accuracy of speed and head rate (against the exact solver and against
// dt = 1e-3 s), and the per-step profile of each real-time case. Prints figures; asserts nothing.
// Usage: flagella_bench_helical [CONFIG_DIR]
// [--quick]
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "flagella_sim/core/sparse_assembler.h"
#include "flagella_sim/core/units.h"
#include "flagella_sim/effects/rss_hydrodynamics.h"
#include "flagella_sim/elastic/bend_twist_energy.h"
#include "flagella_sim/elastic/stretching_energy.h"
#include "flagella_sim/hydro/rss_solver.h"
#include "flagella_sim/outputs/fits.h"
#include "flagella_sim/runtime/tool_main.h"
#include "flagella_sim/simulation/simulation.h"
#include "flagella_sim/solver/dense_jacobian_product.h"
#include "flagella_sim/solver/dense_newton_system.h"
#include "flagella_sim/solver/gmres.h"

using namespace flagella;

namespace {

using Clock = std::chrono::steady_clock;

// The robot's RSS effect, or null when the config has none.
const RssHydrodynamics* rssOf(const Simulation& sim) {
  return sim.stepper().findEffect<RssHydrodynamics>();
}

double secondsOf(const std::function<void()>& work, int repeats) {
  const auto t0 = Clock::now();
  for (int r = 0; r < repeats; ++r) work();
  return std::chrono::duration<double>(Clock::now() - t0).count() / repeats;
}

// The exact solver, as before the rigid reuse and the Newton-Krylov updates (docs/model.md 4.4).
std::vector<std::string> exactSolver(std::vector<std::string> overrides) {
  overrides.push_back("effects.rss.reuse_tolerance=0");
  overrides.push_back("solver.krylov_iterations=0");
  return overrides;
}

// [s] after which the 10 rpm cruise is steady (speed within 1 % of its final value).
constexpr double kSteadyAfter = 6.0;

// Steps past the motor's soft start (steps during the ramp need more Newton updates).
long stepsPastRamp(const SimulationConfig& config) {
  return std::lround((config.motor.ramp_time + 0.5) / config.dt);
}

// Median wall time per step over `steps` steps after `warm` steps.
double secondsPerStep(Simulation& sim, long warm, long steps) {
  for (long k = 0; k < warm; ++k) sim.step();
  std::vector<double> per;
  for (long k = 0; k < steps; ++k) per.push_back(secondsOf([&] { sim.step(); }, 1));
  std::sort(per.begin(), per.end());
  return per[per.size() / 2];
}

// Wall time [s] of each part of one step in the steady cruise.
struct PartCosts {
  double build = 0.0, factor = 0.0, invert = 0.0, elastic = 0.0, newton = 0.0, solve = 0.0,
         gmres_product = 0.0, residual_solve = 0.0;
};

// Counts and median wall time over 100 profiled steps of the steady cruise.
struct SteadySteps {
  StepProfile profile;
  double step = 0.0, per_step = 0.0, reused = 0.0;
};

// The RSS effect's nodes as a polyline of the current state, and their position DOFs.
void rssLine(const RssHydrodynamics& rss, const RodState& s, rss::Polyline& line,
             std::vector<int>& dofs) {
  for (int node : rss.nodes()) {
    line.push_back(nodePosition(s.q, node));
    for (int a = 0; a < 3; ++a) dofs.push_back(RodNetwork::positionIndex(node) + a);
  }
}

// Times the elastic assembly (inertia diagonal, stretching, bend-twist) into `assembler`.
double timeElasticAssembly(const RodNetwork& net, const RodState& s, SparseAssembler& assembler) {
  VecX gradient = VecX::Zero(net.ndof());
  return secondsOf(
      [&] {
        assembler.begin();
        gradient.setZero();
        for (int i = 0; i < net.ndof(); ++i) assembler.add(i, i, net.lumped_mass(i) / 1e-4);
        addStretchingGradientHessian(net, s.frames, gradient, &assembler);
        addBendTwistGradientHessian(net, s.q, s.frames, gradient, &assembler, {});
        assembler.finish();
      },
      50);
}

// Times the dense Newton system's factorisation and solve and one GMRES product.
void timeNewtonParts(const SimulationConfig& config, const RodNetwork& net,
                     const std::vector<int>& dofs, const rss::RssSolver& solver,
                     const SparseMatrix& jacobian, PartCosts& costs) {
  // The dense Newton system as the stepper builds it: sparse part plus the RSS block, right-
  // preconditioned by Ablk (no inverse), factored.
  const VecX weights = solver.dragRowWeights();
  DenseNewtonSystem system;
  costs.newton = secondsOf(
      [&] {
        system.begin(jacobian, net.fixed_dof);
        system.addScaledInverse(dofs, solver, weights, -1.0 / config.dt);
        system.factorize(1e-15);
      },
      20);
  const VecX rhs = VecX::Ones(net.ndof());
  costs.solve = secondsOf([&] { (void)system.solve(rhs); }, 50);
  // One GMRES product as the stepper takes it: the kept factorisation's solve, the mapping by
  // Ablk, and J v without J from the preimage (sparse part, no RSS solve; docs/model.md 4.4).
  DenseJacobianProduct product;
  product.begin(jacobian, net.fixed_dof);
  product.addScaledInverse(dofs, solver, weights, -1.0 / config.dt);
  VecX out(net.ndof()), z, mapped;
  costs.gmres_product = secondsOf(
      [&] {
        system.solveUnmapped(rhs, z);
        system.map(z, mapped);
        product.applyMapped(mapped, z, system.mappingMatrix(), system.mappingScale(), out);
      },
      50);
}

// Profiles 100 steps of a fresh simulation of `config` after its steady-cruise start.
SteadySteps profileSteadySteps(const SimulationConfig& config) {
  SteadySteps out;
  Simulation timed(config);
  for (long k = 0; k < std::lround(kSteadyAfter / config.dt); ++k) timed.step();
  timed.setProfile(&out.profile);
  const auto* timed_rss = rssOf(timed);
  const long rss_steps = timed_rss->stepsAfterFirst(), rss_reused = timed_rss->reusedSteps();
  const int factorizations = timed.stepper().totalFactorizations();
  out.step = secondsPerStep(timed, 0, 100);
  timed.setProfile(nullptr);
  out.per_step = (timed.stepper().totalFactorizations() - factorizations) / 100.0;
  out.reused = double(timed_rss->reusedSteps() - rss_reused) /
               double(std::max(1L, timed_rss->stepsAfterFirst() - rss_steps));
  return out;
}

// Prints the per-part costs and the per-step counts of the breakdown.
void printBreakdown(const PartCosts& c, const SteadySteps& steps, size_t nodes, int ndof) {
  std::printf("per-part cost in the steady 10 rpm cruise (%zu RSS nodes, %d DOFs):\n", nodes, ndof);
  std::printf(
      "  RSS matrix build          %9.1f us  (when the nodes are no rigid motion of the last)\n",
      1e6 * c.build);
  std::printf("  RSS LU factorisation      %9.1f us  (the same)\n", 1e6 * c.factor);
  std::printf("  RSS force (LU solve)      %9.1f us  (per residual evaluation not followed)\n",
              1e6 * c.residual_solve);
  std::printf("  elastic assembly          %9.1f us  (per Jacobian)\n", 1e6 * c.elastic);
  std::printf(
      "  dense Newton system       %9.1f us  (per factorisation: build, precondition, LU)\n",
      1e6 * c.newton);
  std::printf("  dense Newton solve        %9.1f us  (per direct update)\n", 1e6 * c.solve);
  std::printf("  GMRES product             %9.1f us  (one preconditioner solve, C z and J C z)\n",
              1e6 * c.gmres_product);
  std::printf("  (drag matrix by inverse   %9.1f us  not needed: the system is preconditioned)\n",
              1e6 * c.invert);
  std::printf(
      "per step over 100 steps: %.2f Jacobians, %.3f factorisations, %.2f updates, "
      "%.2f GMRES products; RSS factorisation reused rotated on %.0f %% of steps\n",
      steps.profile.jacobians / 100.0, steps.per_step, steps.profile.updates / 100.0,
      steps.profile.krylov_iterations / 100.0, 100.0 * steps.reused);
  std::printf("  whole step (median)       %9.1f us\n", 1e6 * steps.step);
}

void breakdown(const SimulationConfig& config) {
  Simulation sim(config);
  for (long k = 0; k < std::lround(kSteadyAfter / config.dt); ++k) sim.step();  // steady cruise
  const RodNetwork& net = sim.network();
  const RodState& s = sim.state();
  const auto* rss = rssOf(sim);
  if (!rss) {
    std::printf("(no rss effect in the config: no breakdown)\n");
    return;
  }
  rss::Polyline line;
  std::vector<int> dofs;
  rssLine(*rss, s, line, dofs);
  PartCosts costs;
  const double eps = rss->parameters().get("eps");
  MatX ablk;
  costs.build = secondsOf([&] { ablk = rss::assembleRssMatrix(line, eps); }, 20);
  DenseLuSolver lu;
  costs.factor = secondsOf([&] { lu.factorize(ablk); }, 20);
  const rss::RssSolver solver(line, eps, sim.stepper().currentViscosity());
  costs.invert = secondsOf([&] { (void)solver.dragMatrix(); }, 10);
  SparseAssembler assembler(net.ndof());
  costs.elastic = timeElasticAssembly(net, s, assembler);
  timeNewtonParts(config, net, dofs, solver, assembler.matrix(), costs);
  costs.residual_solve =
      secondsOf([&] { (void)solver.nodalForces(VecX::Ones(3 * line.size())); }, 50);
  printBreakdown(costs, profileSteadySteps(config), line.size(), net.ndof());
}

// Per-step cost of each part (StepProfile) over `steps` steps of a running simulation.
void printStepParts(Simulation& sim, long steps) {
  StepProfile profile;
  const RssHydrodynamics* rss = rssOf(sim);
  const long reused_before = rss ? rss->reusedSteps() : 0L;
  const long solves_before = rss ? rss->forceSolves() : 0L;
  sim.setProfile(&profile);
  for (long k = 0; k < steps; ++k) sim.step();
  sim.setProfile(nullptr);
  const double n = double(steps), us = 1e6 / n;
  std::printf(
      "    per step: %.2f Jacobians, %.2f residuals, %.2f factorisations, %.2f updates, %.2f GMRES "
      "products, RSS reused on %.0f %%, %.2f RSS solves (residuals not followed)\n",
      profile.jacobians / n, profile.residuals / n, profile.factorizations / n, profile.updates / n,
      profile.krylov_iterations / n,
      rss ? 100.0 * double(rss->reusedSteps() - reused_before) / n : 0.0,
      rss ? double(rss->forceSolves() - solves_before) / n : 0.0);
  std::printf(
      "    us per step: frames %.0f, elastic %.0f, effects %.0f, assembly %.0f, "
      "factorisation %.0f, solve %.0f, convergence %.0f, other %.0f; total %.0f\n",
      us * profile.frames, us * profile.elastic, us * profile.effects, us * profile.assembly,
      us * profile.factorization, us * profile.solve, us * profile.convergence,
      us * profile.other(), us * profile.total);
}

struct Swim {
  double speed_mm_s, omega_h_rpm, seconds_per_step;
};

Swim swim(const std::string& path, std::vector<std::string> overrides, double dt, double duration) {
  overrides.push_back("simulation.dt=" + std::to_string(dt));
  overrides.push_back("simulation.duration=" + std::to_string(duration));
  const SimulationConfig config = loadSimulationConfig(path, overrides);
  Simulation sim(config);
  const auto t0 = Clock::now();
  sim.run(config.duration);
  const double wall = std::chrono::duration<double>(Clock::now() - t0).count();
  const SummaryMetrics m = sim.summary();
  return {units::metresToMm(m.speed), units::radPerSecToRpm(m.omega_h),
          wall / std::lround(duration / dt)};
}

}  // namespace

int run(const std::string& config_dir, bool quick) {
  const std::string robot = config_dir + "/helical_robot.yaml";
  std::printf("helical robot benchmark (one core), %s\n\n", robot.c_str());
  const std::vector<std::string> base{"motor.omega_rpm=10"};  // cruise, below the threshold
  const SimulationConfig config = loadSimulationConfig(robot, base);
  breakdown(config);

  std::printf(
      "\nreal-time factor at dt = 1e-2 s (3.5 pitches, after the ramp): shipped solver, exact "
      "solver, shipped solver with the rotating predictor (solver.predictor=rotating):\n");
  const char* variants[] = {"shipped solver ", "exact solver   ", "rotating pred. "};
  for (const char* rpm : {"10", "30", "150"}) {
    for (int variant = 0; variant < 3; ++variant) {
      std::vector<std::string> ov{std::string("motor.omega_rpm=") + rpm};
      if (variant == 1) ov = exactSolver(ov);
      if (variant == 2) ov.push_back("solver.predictor=rotating");
      const SimulationConfig c = loadSimulationConfig(robot, ov);
      Simulation sim(c);
      const long steps = quick ? 100 : 500;
      const double per_step = secondsPerStep(sim, stepsPastRamp(c), steps);
      std::printf("  %3s rpm%s, %s: %.1f us/step, %.2fx real time\n", rpm,
                  std::string(rpm) == "150" ? " (buckled)" : " (below the threshold)",
                  variants[variant], 1e6 * per_step, c.dt / per_step);
      printStepParts(sim, quick ? 50 : 200);
    }
  }

  std::printf("\ncost against node count (dt = 1e-2 s):\n%12s %8s %8s %12s\n", "edge [mm]", "nodes",
              "DOFs", "us/step");
  std::vector<double> log_nodes, log_time;
  for (double dl : {10.0, 7.0, 5.0, 3.5, 2.5, 1.75}) {
    std::vector<std::string> ov = base;
    ov.push_back("robot.edge_length=" + std::to_string(dl * 1e-3));
    const SimulationConfig refined = loadSimulationConfig(robot, ov);
    Simulation sim(refined);
    // after the transient of the start (the rotated RSS factorisation serves the steady state)
    const double per_step =
        secondsPerStep(sim, std::lround(kSteadyAfter / refined.dt), quick ? 30 : 100);
    std::printf("%12.1f %8d %8d %12.1f\n", dl, sim.network().numNodes(), sim.network().ndof(),
                1e6 * per_step);
    log_nodes.push_back(std::log(sim.network().numNodes()));
    log_time.push_back(std::log(per_step));
  }
  std::printf("scaling exponent (time per step ~ nodes^p): p = %.2f\n",
              fitLine(log_nodes, log_time).slope);

  const double duration = quick ? 4.0 : 20.0;
  std::printf("\ndt accuracy (10 rpm, %.0f s, steady window = last half):\n", duration);
  const Swim coarse = swim(robot, base, 1e-2, duration);
  const Swim fine = swim(robot, base, 1e-3, duration);
  std::printf("  dt = 1e-2: v = %.5f mm/s, omega_h = %.4f rpm (%.0f us/step)\n", coarse.speed_mm_s,
              coarse.omega_h_rpm, 1e6 * coarse.seconds_per_step);
  std::printf("  dt = 1e-3: v = %.5f mm/s, omega_h = %.4f rpm (%.0f us/step)\n", fine.speed_mm_s,
              fine.omega_h_rpm, 1e6 * fine.seconds_per_step);
  std::printf("  relative difference: v %.2f %%, omega_h %.2f %%\n",
              100.0 * (coarse.speed_mm_s - fine.speed_mm_s) / fine.speed_mm_s,
              100.0 * (coarse.omega_h_rpm - fine.omega_h_rpm) / fine.omega_h_rpm);
  const Swim exact = swim(robot, exactSolver(base), 1e-2, duration);
  std::printf("  dt = 1e-2, exact solver: v = %.5f mm/s, omega_h = %.4f rpm (%.0f us/step)\n",
              exact.speed_mm_s, exact.omega_h_rpm, 1e6 * exact.seconds_per_step);
  std::printf("  shipped against exact solver: v %+.4f %%, omega_h %+.4f %%\n",
              100.0 * (coarse.speed_mm_s - exact.speed_mm_s) / exact.speed_mm_s,
              100.0 * (coarse.omega_h_rpm - exact.omega_h_rpm) / exact.omega_h_rpm);
  return 0;
}

int main(int argc, char** argv) {
  CLI::App app{
      "flagella_bench_helical: real-time factor, per-part step cost, cost against node "
      "count and dt accuracy of the helical robot (prints figures)"};
  std::string config_dir = "config";
  bool quick = false;
  app.add_option("config_dir", config_dir, "folder holding helical_robot.yaml")
      ->capture_default_str();
  app.add_flag("--quick", quick, "fewer steps and a 4 s accuracy run");
  if (const auto exit_code = flagella::cli::parseArguments(app, argc, argv)) return *exit_code;
  return flagella::cli::runGuarded([&] { return run(config_dir, quick); });
}
