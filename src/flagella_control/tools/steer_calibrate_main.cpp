// flagella_steer_calibrate: the mass-transformer controller's calibration from the simulator
// (docs/model.md 7.4): buckling threshold, cruise speed, both buckle schedules' deflection and
// phase law, slider pitch rate. Writes YAML for flagella_steer and the steering node.
//   flagella_steer_calibrate config/helical_steering.yaml -o
//   config/calibration/helical_steering.yaml
#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <iostream>

#include "flagella_control/steering_calibration_runner.h"
#include "flagella_sim/core/parameter_set.h"
#include "flagella_sim/runtime/tool_main.h"

int main(int argc, char** argv) {
  CLI::App app{"Steering calibration of the helical robot with a mass-transformer"};
  std::string config_path, output;
  std::vector<std::string> overrides;
  flagella::control::SteeringCalibrationOptions options;
  app.add_option("config", config_path, "robot config YAML with a slider: section")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("-o,--output", output, "calibration YAML to write")->required();
  app.add_option("--set", overrides, "config override a.b=value (repeatable)");
  app.add_option("--threshold-rpm", options.threshold_rpm,
                 "buckling threshold if known [rpm] (default: searched)");
  app.add_option("--cruise-fraction", options.cruise_fraction, "cruise rate / threshold");
  app.add_option("--pulse-factor", options.pulse_factor, "pulse rate / threshold");
  app.add_option("--pulse-duration", options.pulse_duration, "buckle pulse [s]");
  app.add_option("--relax-duration", options.relax_duration, "relax schedule: rest after [s]");
  app.add_option("--lead-duration", options.lead_duration, "three-level: rest before [s]");
  app.add_option("--pulses", options.pulses, "calibration pulses per schedule");
  app.add_option("--crab-step", options.crab_step,
                 "crab runs: slider offsets +- this from the park position [m]");
  app.add_option("--crab-measure", options.crab_measure, "crab runs: measured span [s]");
  if (const auto exit_code = flagella::cli::parseArguments(app, argc, argv)) return *exit_code;
  return flagella::cli::runGuarded([&] {
    const auto t0 = std::chrono::steady_clock::now();
    const flagella::SimulationConfig config =
        flagella::loadSimulationConfig(config_path, overrides);
    const auto calibration = flagella::control::calibrateSteering(
        config, options, [](const std::string& line) { std::printf("%s\n", line.c_str()); });
    flagella::control::saveSteeringCalibration(calibration, output);
    std::printf("wrote %s (%.0f s)\n", output.c_str(),
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    return 0;
  });
}
