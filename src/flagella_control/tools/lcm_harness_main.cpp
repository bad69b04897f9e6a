// flagella_lcm_harness: the core simulator driven by a controller core over LCM, with no ROS
// master. Prints what was exchanged and where the robot went.
//   flagella_lcm_harness config/interface_path_planning.yaml --duration 60 --omega-rpm 43.27
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <iostream>

#include "flagella_control/lcm_harness.h"
#include "flagella_sim/core/parameter_set.h"
#include "flagella_sim/core/units.h"
#include "flagella_sim/runtime/tool_main.h"
#include "flagella_sim/simulation/simulation_config.h"

int main(int argc, char** argv) {
  CLI::App app{"Core simulator + controller core over LCM (no ROS)"};
  std::string config_path;
  std::vector<std::string> overrides;
  double duration = 30.0, omega_rpm = 43.27, positive = 5.0, negative = 5.0;
  flagella::control::HarnessOptions options;
  flagella::SessionOptions session_options;
  session_options.initial_motor = "stopped";
  app.add_option("config", config_path, "robot config YAML")->required()->check(CLI::ExistingFile);
  app.add_option("--set", overrides, "config override a.b=value (repeatable)");
  app.add_option("--duration", duration, "simulated seconds")->check(CLI::PositiveNumber);
  app.add_option("--omega-rpm", omega_rpm, "periodic-switch controller: motor rate [rpm]")
      ->check(CLI::PositiveNumber);
  app.add_option("--positive", positive, "time at +omega per period [s]")
      ->check(CLI::PositiveNumber);
  app.add_option("--negative", negative, "time at -omega per period [s]")
      ->check(CLI::PositiveNumber);
  app.add_option("--lcm-url", options.lcm_url, "LCM provider (memq:// keeps it in the process)");
  app.add_option("--imu-rate", session_options.imu.rate, "IMU rate [Hz]")
      ->check(CLI::PositiveNumber);
  app.add_option("--state-rate", options.state_rate, "rod state rate [Hz]")
      ->check(CLI::PositiveNumber);
  if (const auto exit_code = flagella::cli::parseArguments(app, argc, argv)) return *exit_code;

  return flagella::cli::runGuarded([&] {
    const flagella::SimulationConfig config =
        flagella::loadSimulationConfig(config_path, overrides);
    flagella::SimSession session(config, session_options);
    flagella::control::PeriodicSwitchController controller(
        flagella::units::rpmToRadPerSec(omega_rpm), positive, negative);
    flagella::control::LcmHarness harness(session, controller, options);
    const flagella::RodSnapshot start = session.snapshot();
    const flagella::control::HarnessReport report = harness.run(duration);
    const flagella::RodSnapshot end = session.snapshot();
    std::printf("simulated %.3f s in %.3f s wall (%.1fx real time), %ld steps%s\n", report.sim_time,
                report.wall_seconds, report.sim_time / report.wall_seconds, report.steps,
                report.halted ? ", HALTED by a solver failure" : "");
    for (const auto& [channel, count] : report.published)
      std::printf("  published %-28s %ld\n", channel.c_str(), count);
    for (const auto& [channel, count] : report.received)
      std::printf("  received  %-28s %ld\n", channel.c_str(), count);
    const flagella::Vec3 moved = end.head_position - start.head_position;
    std::printf("head moved (%.2f, %.2f, %.2f) mm; motor commands rejected: %ld\n",
                flagella::units::metresToMm(moved.x()), flagella::units::metresToMm(moved.y()),
                flagella::units::metresToMm(moved.z()), session.health().motor_rejected);
    return report.halted ? 3 : 0;
  });
}
