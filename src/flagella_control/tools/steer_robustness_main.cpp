// flagella_steer_robustness: the mass-transformer closed loop over seeded runs with a wrong model
// (+-error in eps, E, C_t, C_r, l_0, signs drawn per seed) and noisy sensors, against the
// open-loop schedule from the nominal model replayed blind; nominal runs beside them; one mission
// or a set (several --waypoints files). Prints the success rates and miss distances (per mission
// and per seed for a set); writes every run as JSON.
//   flagella_steer_robustness --config config/helical_steering.yaml
//       --waypoints config/paths/steering_demo.yaml
//       --calibration config/calibration/helical_steering.yaml --runs 10 --jobs 2 --json r.json
#include <CLI/CLI.hpp>
#include <cstdio>
#include <fstream>
#include <iostream>

#include "flagella_control/steering_robustness.h"
#include "flagella_sim/core/parameter_set.h"
#include "flagella_sim/runtime/parallel_for.h"
#include "flagella_sim/runtime/tool_main.h"
#include "steering_cli.h"

int main(int argc, char** argv) {
  CLI::App app{"Robustness of the mass-transformer closed loop against model error and noise"};
  flagella::control::RobustnessOptions options;
  options.jobs = flagella::defaultJobs();
  flagella::control::cli::SteeringInputs inputs;
  std::string json_path;
  inputs.addTo(app, true);
  app.add_option("--runs", options.runs, "seeded runs per kind (default 10)")
      ->check(CLI::Range(1, 10000));
  app.add_option("--error", options.error, "relative model error of each key (default 0.2)")
      ->check(CLI::Range(0.0, 0.9));
  app.add_option(
      "--keys", options.keys,
      "model values made wrong (default: eps E C_t C_r l_0; also m_s: slider mass, k_t: motor "
      "torque constant, as the stall torque of effects.dc_motor, or any "
      "section.field)");
  app.add_option("--first-seed", options.first_seed, "seed of the first run (default 1)");
  app.add_option("--jobs", options.jobs, "runs at once (default: the core count)")
      ->check(CLI::Range(1, 64));
  app.add_option("--max-duration", options.max_duration,
                 "simulated seconds per run before giving up (default 600)")
      ->check(CLI::Range(1.0, 1e5));
  app.add_flag("!--no-nominal", options.nominal, "skip the nominal closed-loop runs");
  app.add_flag("!--no-replay", options.replay,
               "skip the reference runs and the nominal schedule's blind replays (closed loops "
               "only)");
  app.add_option("--json", json_path, "write every run as JSON");
  if (const auto exit_code = flagella::cli::parseArguments(app, argc, argv)) return *exit_code;
  return flagella::cli::runGuarded([&] {
    inputs.config(inputs.overrides);  // refused early: no slider, bad fields
    options.config_path = inputs.config_path;
    options.overrides = inputs.overrides;
    const auto calibration = inputs.calibration();
    const auto missions = inputs.missions();
    const auto report = flagella::control::runRobustness(
        options, calibration, missions, inputs.gains(), [](const std::string& line) {
          std::printf("%s\n", line.c_str());
          std::fflush(stdout);
        });
    std::printf("\n%s", flagella::control::robustnessSummary(report).c_str());
    std::printf("%zu runs in %.0f s wall (%d jobs)\n", report.runs.size(), report.wall_seconds,
                options.jobs);
    if (!json_path.empty()) {
      std::ofstream json(json_path);
      json << flagella::control::robustnessJson(report);
      if (!json) throw std::runtime_error("cannot write " + json_path);
    }
    for (const auto& run : report.runs)
      if (!run.error.empty()) {
        std::fprintf(stderr, "error: %s, %s, seed %u: %s\n", report.missions[run.mission].c_str(),
                     run.kind.c_str(), run.seed, run.error.c_str());
        return 1;
      }
    return 0;
  });
}
