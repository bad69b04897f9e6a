// flagella_tracking_bound: the smallest cross-track error any schedule of the binary input can
// achieve on a path, with perfect state knowledge, on the calibrated model (docs/model.md 7.5).
//   flagella_tracking_bound --calibration config/calibration/interface_path_planning.yaml
//       --path config/paths/square.yaml [--refine] [--json bound.json] [--csv bound.csv]
#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>

#include "flagella_control/path_controllers.h"
#include "flagella_control/path_spec.h"
#include "flagella_control/tracking_bound_report.h"
#include "flagella_sim/runtime/tool_main.h"

int main(int argc, char** argv) {
  namespace fc = flagella::control;
  CLI::App app{"Tracking bound of a path for the binary input, on the calibrated model"};
  std::string calibration_path, path_path, json_path, csv_path;
  double tail_length = 0.11;
  bool refine = false;
  fc::TrackingBoundOptions options;
  app.add_option("--calibration", calibration_path, "calibration YAML (flagella_calibrate)")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("--path", path_path, "path YAML (config/paths)")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("--duty-steps", options.duty_steps, "shares of +omega per period, 1..1000");
  app.add_option("--sample-interval", options.sample_interval, "error sampled every [s]");
  app.add_option("--states-per-progress", options.states_per_progress,
                 "states kept per progress cell");
  app.add_option("--tail-length", tail_length, "l [m], the unit of the printed errors")
      ->check(CLI::Range(1e-4, 10.0));
  app.add_flag("--refine", refine,
               "also search on a grid twice as fine (duty steps, cells) and print both");
  app.add_option("--json", json_path, "write the figures as JSON");
  app.add_option("--csv", csv_path, "write the head path of the max-error schedule as CSV");
  if (const auto exit_code = flagella::cli::parseArguments(app, argc, argv)) return *exit_code;

  return flagella::cli::runGuarded([&] {
    const fc::BinaryCalibration calibration = fc::loadCalibration(calibration_path);
    const fc::PathSpec spec = fc::loadPathSpec(path_path);
    const fc::Path path = fc::anchorPath(spec, calibration, fc::Vec2::Zero(), 0.0);
    const auto timed = [&](const fc::TrackingBoundOptions& o) {
      const auto start = std::chrono::steady_clock::now();
      const fc::TrackingBound bound = fc::computeTrackingBound(path, spec.laps, calibration, o);
      const double wall =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      std::printf("%s\n", fc::describeBound(bound, tail_length).c_str());
      std::printf(
          "  searched %ld period choices in %.1f s (duty steps %d, cells %.1f mm / %.1f mm / "
          "%.3f rad)\n",
          bound.states_expanded, wall, o.duty_steps, 1e3 * o.progress_cell,
          1e3 * o.cross_track_cell, o.heading_cell);
      return bound;
    };
    std::printf("tracking bound on %s (one sign per period share, T = %.1f s, perfect state):\n",
                spec.description.c_str(), calibration.switch_period);
    const fc::TrackingBound bound = timed(options);
    std::printf(
        "  model: dead time %.2f s after a switch, advance direction off the measured one "
        "by %.1f deg\n",
        bound.dead_time, bound.direction_mismatch * 180.0 / M_PI);
    if (refine) timed(fc::refinedOptions(options));
    if (!bound.best_max.complete)
      throw std::runtime_error("no schedule completes the path within " +
                               std::to_string(options.max_duration) + " s");
    if (!json_path.empty()) fc::writeBoundJson(bound, json_path);
    if (!csv_path.empty()) {
      std::ofstream csv(csv_path);
      if (!csv) throw std::runtime_error("cannot write " + csv_path);
      csv << "x,y\n";
      for (const fc::Vec2& p : bound.best_max.samples) csv << p.x() << "," << p.y() << "\n";
    }
    return 0;
  });
}
