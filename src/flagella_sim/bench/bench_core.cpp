// Benchmark program: where a step of the shipped robots spends its time (profile by part, with the
// block LU and with KLU), their real-time factor and step time against one factorization + solve
// of either, and time per step against node count (with the fitted scaling exponent). Prints
// figures; asserts nothing.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "flagella_sim/outputs/fits.h"
#include "flagella_sim/runtime/tool_main.h"
#include "flagella_sim/simulation/simulation.h"

using namespace flagella;

namespace {

constexpr int kRepeats = 3;             // median of this many timed runs
constexpr double kWarmupSeconds = 5.0;  // simulated time before timing (start-up transient)

struct Timing {
  double seconds_per_step;
  double real_time_factor;
  double newton_per_step;
};

Timing timeConfig(const std::string& path, const std::vector<std::string>& overrides,
                  double sim_seconds) {
  std::vector<double> per_step, iterations;
  double dt = 0.0;
  for (int r = 0; r < kRepeats; ++r) {
    const SimulationConfig config = loadSimulationConfig(path, overrides);
    dt = config.dt;
    Simulation sim(config);
    const long warm = std::lround(kWarmupSeconds / dt);
    for (long k = 0; k < warm; ++k) sim.step();
    const long steps = std::lround(sim_seconds / dt);
    long newton = 0;
    const auto t0 = std::chrono::steady_clock::now();
    for (long k = 0; k < steps; ++k) newton += sim.step().newton_iterations;
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    per_step.push_back(wall / steps);
    iterations.push_back(static_cast<double>(newton) / steps);
  }
  std::sort(per_step.begin(), per_step.end());
  const double median = per_step[kRepeats / 2];
  return {median, dt / median, iterations.back()};
}

// One profiled run (Simulation::run, so with its output sampling): where a step's time goes.
// Returns the time of one factorization plus one solve [s].
double printProfile(const std::string& label, const std::string& path,
                    const std::vector<std::string>& overrides, double sim_seconds) {
  const SimulationConfig config = loadSimulationConfig(path, overrides);
  Simulation sim(config);
  sim.run(kWarmupSeconds);
  StepProfile p;
  sim.setProfile(&p);
  const auto t0 = std::chrono::steady_clock::now();
  sim.run(sim_seconds);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  sim.setProfile(nullptr);
  const double n = static_cast<double>(p.steps);
  auto us = [&](double seconds) { return 1e6 * seconds / n; };
  const double factor_solve = (p.factorizations ? p.factorization / p.factorizations : 0.0) +
                              (p.updates ? p.solve / p.updates : 0.0);
  std::printf("%s: us per step by part (profiled run of %.0f s, with output)\n", label.c_str(),
              sim_seconds);
  std::printf(
      "  frames %.1f | elastic %.1f | effects %.1f | assembly %.1f | factorization %.1f | "
      "solve %.1f | convergence %.1f | other %.1f | output %.1f | step %.1f\n",
      us(p.frames), us(p.elastic), us(p.effects), us(p.assembly), us(p.factorization), us(p.solve),
      us(p.convergence), us(p.other()), us(wall - p.total), us(wall));
  std::printf(
      "  per step: %.2f Newton updates, %.2f residuals, %.3f Jacobians, %.3f factorizations;"
      " one factorization + solve %.1f us; step / (factorization + solve) = %.2f\n",
      p.updates / n, p.residuals / n, p.jacobians / n, p.factorizations / n, 1e6 * factor_solve,
      factor_solve > 0 ? (wall / n) / factor_solve : 0.0);
  const double residual_only = p.residuals - p.jacobians;
  std::printf(
      "  one evaluation (frames excluded): residual only %.1f us, residual + Jacobian %.1f us\n",
      residual_only > 0 ? 1e6 * p.residual_evaluations / residual_only : 0.0,
      p.jacobians ? 1e6 * p.jacobian_evaluations / p.jacobians : 0.0);
  return factor_solve;
}

}  // namespace

int run(const std::string& config_dir) {
  std::printf("flagella core benchmark (one core, median of %d runs, after %.0f s warm-up)\n\n",
              kRepeats, kWarmupSeconds);
  std::printf(
      "where a step's time goes (LU + solve: one sparse factorization and one solve; the block\n"
      "LU is the default linear solver, KLU its pivoting fallback, solver.linear_solver)\n");
  struct Case {
    std::string label, file;
    std::vector<std::string> overrides;
  };
  const std::vector<Case> cases{
      {"design 1, n = 3, 100 rpm, dt = 1e-2",
       "granular_design1.yaml",
       {"robot.n_tails=3", "motor.omega_rpm=100", "simulation.dt=0.01"}},
      {"design 1, n = 2, 100 rpm, dt = 1e-2",
       "granular_design1.yaml",
       {"robot.n_tails=2", "motor.omega_rpm=100", "simulation.dt=0.01"}},
      {"interface robot, N = 2, dt = 1e-2",
       "interface_robot.yaml",
       {"robot.n_tails=2", "simulation.dt=0.01"}},
  };
  auto withKlu = [](std::vector<std::string> overrides) {
    overrides.push_back("solver.linear_solver=klu");
    return overrides;
  };
  std::vector<double> block_solve, klu_solve;
  for (const Case& c : cases) {
    const std::string path = config_dir + "/" + c.file;
    block_solve.push_back(printProfile(c.label + " (block LU)", path, c.overrides, 20.0));
    klu_solve.push_back(printProfile(c.label + " (KLU)", path, withKlu(c.overrides), 20.0));
  }
  std::printf("\n%-38s %6s %9s %11s %11s %16s %14s %12s\n", "case (block LU)", "DOFs", "us/step",
              "real-time x", "Newton/step", "step/(LU+solve)", "step/(KLU+solve)", "us/step KLU");
  for (size_t k = 0; k < cases.size(); ++k) {
    const Case& c = cases[k];
    const std::string path = config_dir + "/" + c.file;
    const SimulationConfig config = loadSimulationConfig(path, c.overrides);
    const int dofs = Simulation(config).network().ndof();
    const Timing t = timeConfig(path, c.overrides, 20.0);
    const Timing klu = timeConfig(path, withKlu(c.overrides), 20.0);
    std::printf("%-38s %6d %9.1f %11.1f %11.2f %16.2f %16.2f %12.1f\n", c.label.c_str(), dofs,
                1e6 * t.seconds_per_step, t.real_time_factor, t.newton_per_step,
                t.seconds_per_step / block_solve[k], t.seconds_per_step / klu_solve[k],
                1e6 * klu.seconds_per_step);
  }

  std::printf("\ntime per step against node count (design 1, n = 3, 100 rpm, dt = 1e-2)\n");
  std::printf("%10s %10s %12s\n", "nodes", "DOFs", "us/step");
  std::vector<double> log_nodes, log_time;
  for (int edges : {14, 27, 54, 108, 216}) {
    const std::vector<std::string> ov{"robot.n_tails=3", "motor.omega_rpm=100",
                                      "simulation.dt=0.01",
                                      "robot.tail_edges=" + std::to_string(edges)};
    const SimulationConfig config = loadSimulationConfig(config_dir + "/granular_design1.yaml", ov);
    const Simulation probe(config);
    const Timing t = timeConfig(config_dir + "/granular_design1.yaml", ov, 5.0);
    std::printf("%10d %10d %12.1f\n", probe.network().numNodes(), probe.network().ndof(),
                1e6 * t.seconds_per_step);
    log_nodes.push_back(std::log(probe.network().numNodes()));
    log_time.push_back(std::log(t.seconds_per_step));
  }
  std::printf("scaling exponent (time per step ~ nodes^p): p = %.2f\n",
              fitLine(log_nodes, log_time).slope);
  return 0;
}

int main(int argc, char** argv) {
  CLI::App app{
      "flagella_bench: time per step and real-time factor of the shipped robots "
      "(prints figures)"};
  std::string config_dir = "config";
  app.add_option("config_dir", config_dir, "folder holding the shipped configs")
      ->capture_default_str();
  if (const auto exit_code = flagella::cli::parseArguments(app, argc, argv)) return *exit_code;
  return flagella::cli::runGuarded([&] { return run(config_dir); });
}
