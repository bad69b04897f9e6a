// flagella_steer: the helical robot steered through 3-D waypoints by the mass-transformer
// controller, headless (core simulator and controller core over LCM memq://, no ROS). The model
// may be made wrong (--model-error) against the calibration; sensors are noisy and seeded.
// Writes JSON (reached, total, max_miss_mm, time_s, mode timeline) and a CSV of the path.
//   flagella_steer --config config/helical_steering.yaml --waypoints
//   config/paths/steering_demo.yaml
//       --calibration config/calibration/helical_steering.yaml --json /tmp/steer.json
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>

#include "flagella_control/steering_run.h"
#include "flagella_sim/core/parameter_set.h"
#include "flagella_sim/runtime/progress_printer.h"
#include "flagella_sim/runtime/tool_main.h"
#include "steering_cli.h"

int main(int argc, char** argv) {
  CLI::App app{"3-D waypoint steering of the helical robot (mass-transformer closed loop)"};
  flagella::control::cli::SteeringInputs inputs;
  std::string json_path, csv_path;
  std::vector<std::string> errors_text;
  unsigned seed = 1;
  double max_duration = 0.0;
  inputs.addTo(app);
  app.add_option("--model-error", errors_text,
                 "key=factor: scale a model value the calibration assumed (eps, E, C_t, C_r, l_0 "
                 "or section.field; repeatable)");
  app.add_option("--seed", seed, "sensor noise seed")->capture_default_str();
  app.add_option("--max-duration", max_duration,
                 "give up after this many simulated seconds (default: simulation.duration)");
  app.add_option("--json", json_path, "write the result as JSON");
  app.add_option("--csv", csv_path, "write the true and estimated path as CSV (for the plot)");
  if (const auto exit_code = flagella::cli::parseArguments(app, argc, argv)) return *exit_code;
  return flagella::cli::runGuarded([&] {
    std::vector<std::pair<std::string, double>> errors;
    for (const std::string& e : errors_text)
      errors.push_back(flagella::control::cli::assignment(e, "--model-error", "key=factor"));
    const flagella::SimulationConfig config = inputs.config(
        flagella::control::modelErrorOverrides(inputs.config_path, inputs.overrides, errors));
    const auto calibration = inputs.calibration();
    const auto mission = inputs.mission();
    flagella::control::MassTransformerController controller(mission, calibration, inputs.gains());
    const double duration = max_duration > 0.0 ? max_duration : config.duration;
    flagella::ProgressPrinter printer(duration, false);
    const auto progress = [&](double time) {
      const auto& status = controller.status();
      printer(time / duration, "waypoint " + std::to_string(status.reached) + " of " +
                                   std::to_string(controller.mission().points.size()) +
                                   " reached, " + flagella::control::steeringModeName(status.mode));
    };
    const auto result = flagella::control::runSteering(
        config, flagella::control::steeringSessionOptions(config, calibration, seed), controller,
        duration, 0.5, nullptr, progress);
    std::printf(
        "%s, %s schedule: %d of %d waypoints reached (%d in order; tolerance %.1f mm), max "
        "miss %.1f mm, %s after %.1f s simulated (%.1f s wall), %ld buckle cycles\n",
        mission.description.c_str(), inputs.schedule.c_str(), result.reached, result.total,
        result.reached_in_order, mission.tolerance * 1e3, result.max_miss * 1e3,
        result.finished ? "finished" : "NOT finished", result.time, result.wall_seconds,
        result.cycles);
    std::string reach_times;
    for (double t : result.reach_time)
      reach_times += (reach_times.empty() ? "" : ", ") +
                     (std::isnan(t) ? std::string("-") : std::to_string(std::lround(t)) + " s");
    std::printf(
        "reached in order at: %s; slider used %.2f to %.2f mm (%.2f mm of travel); solver: %ld "
        "subdivided steps, %ld damped, %ld retried with the motor stopped\n",
        reach_times.c_str(), result.slider_low * 1e3, result.slider_high * 1e3,
        (result.slider_high - result.slider_low) * 1e3, result.subdivided_steps,
        result.damped_steps, result.motor_stop_retries);
    if (result.halted) std::fprintf(stderr, "simulator halted: %s\n", result.halt_reason.c_str());
    if (!json_path.empty()) {
      std::ofstream json(json_path);
      json << flagella::control::steeringResultJson(result, controller.name(), mission.description);
      if (!json) throw std::runtime_error("cannot write " + json_path);
    }
    if (!csv_path.empty()) {
      std::ofstream csv(csv_path);
      csv << flagella::control::steeringPathCsv(result);
      if (!csv) throw std::runtime_error("cannot write " + csv_path);
    }
    return result.halted ? 3 : result.reached == result.total ? 0 : 4;
  });
}
