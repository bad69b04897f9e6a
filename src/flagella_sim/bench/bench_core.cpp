// Benchmark program: real-time factor of the shipped robots and time per step against node
// count (with the fitted scaling exponent). Prints figures; asserts nothing.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "flagella_sim/outputs/fits.h"
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

}  // namespace

int run(const std::string& config_dir) {
  std::printf("flagella core benchmark (one core, median of %d runs, after %.0f s warm-up)\n\n",
              kRepeats, kWarmupSeconds);
  std::printf("%-44s %10s %12s %14s %10s\n", "case", "DOFs", "us/step", "real-time x",
              "Newton/step");
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
  for (const Case& c : cases) {
    const SimulationConfig config = loadSimulationConfig(config_dir + "/" + c.file, c.overrides);
    const int dofs = Simulation(config).network().ndof();
    const Timing t = timeConfig(config_dir + "/" + c.file, c.overrides, 20.0);
    std::printf("%-44s %10d %12.1f %14.1f %10.2f\n", c.label.c_str(), dofs,
                1e6 * t.seconds_per_step, t.real_time_factor, t.newton_per_step);
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
  CLI11_PARSE(app, argc, argv);
  try {
    return run(config_dir);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  }
}
