// flagella_steer_calibrate: the mass-transformer controller's calibration from the simulator
// (docs/model.md 7.4): buckling threshold, cruise speed, both buckle schedules' deflection and
// phase law, slider pitch rate. Writes YAML for flagella_steer and the steering node; optionally
// the response tables (steering_response_tables.h) as CSV.
//   flagella_steer_calibrate config/helical_steering.yaml -o
//   config/calibration/helical_steering.yaml
#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <iostream>

#include "flagella_control/steering_calibration_runner.h"
#include "flagella_control/steering_response_tables.h"
#include "flagella_sim/core/parameter_set.h"
#include "flagella_sim/runtime/tool_main.h"

namespace {

// The command line's values.
struct CalibrateArgs {
  std::string config_path, output;
  std::vector<std::string> overrides;
  flagella::control::SteeringCalibrationOptions options;
  flagella::control::SteeringTableOptions tables;
  std::string turn_table, slider_table;
  double flip_elevation_deg = 0.0;
};

// Declares the config, output and calibration options, bound to `a`.
void addCalibrationOptions(CLI::App& app, CalibrateArgs& a) {
  app.add_option("config", a.config_path, "robot config YAML with a slider: section")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("-o,--output", a.output, "calibration YAML to write")->required();
  app.add_option("--set", a.overrides, "config override a.b=value (repeatable)");
  app.add_option("--threshold-rpm", a.options.threshold_rpm,
                 "buckling threshold if known [rpm] (default: searched)");
  app.add_option("--cruise-fraction", a.options.cruise_fraction, "cruise rate / threshold");
  app.add_option("--pulse-factor", a.options.pulse_factor, "pulse rate / threshold");
  app.add_option("--pulse-duration", a.options.pulse_duration, "buckle pulse [s]");
  app.add_option("--relax-duration", a.options.relax_duration, "relax schedule: rest after [s]");
  app.add_option("--lead-duration", a.options.lead_duration, "three-level: rest before [s]");
  app.add_option("--pulses", a.options.pulses, "calibration pulses per schedule");
  app.add_option("--slider-pulses", a.options.slider_pulses,
                 "cycles with the slider held off park, per side and schedule (0: skip)")
      ->capture_default_str();
  app.add_option("--cycle-slider-step", a.options.cycle_slider_step, "that offset from park [m]")
      ->capture_default_str();
  app.add_option("--crab-step", a.options.crab_step,
                 "crab runs: slider offsets +- this from the park position [m]");
  app.add_option("--crab-measure", a.options.crab_measure, "crab runs: measured span [s]");
}

// Declares the response-table options (turn table, slider table), bound to `a`.
void addTableOptions(CLI::App& app, CalibrateArgs& a) {
  a.flip_elevation_deg = a.tables.flip_elevation * 180.0 / M_PI;
  auto* turn = app.add_option("--turn-table", a.turn_table,
                              "also write the turn of one buckle cycle against pulse rate and "
                              "duration (both schedules) to this CSV");
  app.add_option("--pulse-factors", a.tables.pulse_factors,
                 "turn table: pulse rates / threshold, e.g. 1.5,2,3")
      ->delimiter(',')
      ->needs(turn);
  app.add_option("--pulse-durations", a.tables.pulse_durations,
                 "turn table: pulse durations [s], e.g. 2,4,6")
      ->delimiter(',')
      ->needs(turn);
  turn->needs(app.get_option("--pulse-factors"))->needs(app.get_option("--pulse-durations"));
  auto* slider = app.add_option("--slider-table", a.slider_table,
                                "also write the slider's response (pitch rate, flip and return "
                                "times, held elevation, azimuth rate, azimuth turned holding "
                                "and returning) against its offset from park to this CSV");
  app.add_option("--slider-offsets", a.tables.slider_offsets,
                 "slider table: offsets from the park position [m], e.g. 5e-4,-5e-4,2e-3")
      ->delimiter(',')
      ->needs(slider);
  slider->needs(app.get_option("--slider-offsets"));
  app.add_option("--flip-elevation", a.flip_elevation_deg,
                 "slider table: |head axis elevation| that counts as flipped [deg]")
      ->capture_default_str();
  app.add_option("--flip-timeout", a.tables.flip_timeout, "slider table: per flip or return [s]")
      ->capture_default_str();
  app.add_option("--hold-window", a.tables.hold_window,
                 "slider table: the end of the hold (to the flip or the timeout) over which the "
                 "held elevation and the azimuth rate are fitted [s]")
      ->capture_default_str();
}

// Measures and writes the requested response tables (none, either or both).
void writeTables(const flagella::SimulationConfig& config,
                 const flagella::control::SteeringCalibration& calibration,
                 const CalibrateArgs& a) {
  const auto print = [](const std::string& line) { std::printf("%s\n", line.c_str()); };
  if (!a.turn_table.empty()) {
    flagella::control::writeBuckleTurnTable(
        flagella::control::measureBuckleTurnTable(config, calibration, a.tables, a.options, print),
        a.turn_table);
    std::printf("wrote %s\n", a.turn_table.c_str());
  }
  if (!a.slider_table.empty()) {
    flagella::control::writeSliderTable(
        flagella::control::measureSliderTable(config, calibration, a.tables, a.options, print),
        a.slider_table);
    std::printf("wrote %s\n", a.slider_table.c_str());
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Steering calibration of the helical robot with a mass-transformer"};
  CalibrateArgs a;
  addCalibrationOptions(app, a);
  addTableOptions(app, a);
  if (const auto exit_code = flagella::cli::parseArguments(app, argc, argv)) return *exit_code;
  a.tables.flip_elevation = a.flip_elevation_deg * M_PI / 180.0;
  return flagella::cli::runGuarded([&] {
    a.tables.validate();  // before the runs, so that a bad option costs no minutes
    const auto t0 = std::chrono::steady_clock::now();
    const flagella::SimulationConfig config =
        flagella::loadSimulationConfig(a.config_path, a.overrides);
    const auto calibration = flagella::control::calibrateSteering(
        config, a.options, [](const std::string& line) { std::printf("%s\n", line.c_str()); });
    flagella::control::saveSteeringCalibration(calibration, a.output);
    writeTables(config, calibration, a);
    std::printf("wrote %s (%.0f s)\n", a.output.c_str(),
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    return 0;
  });
}
