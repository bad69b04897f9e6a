// flagella_follow_path: the interface robot follows a path, headless, with the controller core
// talking to the core simulator over LCM (memq://, no ROS master). Prints the cross-track
// error of the true head path against the reference and writes the path as CSV.
//   flagella_follow_path config/interface_path_planning.yaml
//       --calibration config/calibration/interface_path_planning.yaml --path
//       config/paths/square.yaml
#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>

#include "flagella_control/lcm_harness.h"
#include "flagella_control/path_controllers.h"
#include "flagella_control/receding_horizon_controller.h"
#include "flagella_control/timed_controller.h"
#include "flagella_control/tracking_bound_report.h"
#include "flagella_control/tracking_metrics.h"
#include "flagella_sim/core/parameter_set.h"
#include "flagella_sim/core/units.h"
#include "flagella_sim/runtime/log_throttle.h"
#include "flagella_sim/runtime/tool_main.h"
#include "flagella_sim/simulation/simulation_config.h"

namespace {
constexpr double kProgressPeriod = 10.0;  // [s wall] between progress lines on stderr
}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Path following over LCM: core simulator + controller core (no ROS)"};
  std::string config_path, calibration_path, path_path, mode = "receding_horizon", csv_path;
  std::vector<std::string> overrides;
  double max_duration = 3000.0, sample_interval = 0.5;
  flagella::control::HarnessOptions options;
  flagella::control::PathFollowingGains gains;
  flagella::control::RecedingHorizonGains horizon_gains;
  flagella::SessionOptions session_options;
  session_options.initial_motor = "stopped";
  app.add_option("config", config_path, "robot config YAML")->required()->check(CLI::ExistingFile);
  app.add_option("--calibration", calibration_path, "calibration YAML (flagella_calibrate)")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("--path", path_path, "path YAML (config/paths)")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("--mode", mode, "receding_horizon, closed_loop or open_loop")
      ->check(CLI::IsMember({"receding_horizon", "closed_loop", "open_loop"}));
  app.add_option("--set", overrides, "config override a.b=value (repeatable), e.g. a model error");
  app.add_option("--max-duration", max_duration, "give up after this many simulated seconds")
      ->check(CLI::PositiveNumber);
  app.add_option("--imu-orientation-noise", session_options.imu.orientation_noise_std,
                 "IMU orientation noise std [rad]");
  app.add_option("--imu-gyro-noise", session_options.imu.gyro_noise_std, "gyro noise std [rad/s]");
  app.add_option("--camera-rate", session_options.camera.rate, "camera fixes per second [Hz]");
  app.add_option("--camera-noise", session_options.camera.noise_std, "camera noise std [m]");
  app.add_option("--seed", session_options.imu.seed, "noise seed (IMU; camera uses seed + 1)");
  app.add_option("--horizon", horizon_gains.horizon,
                 "receding horizon: switching periods looked ahead (1..3)");
  app.add_option("--heading-weight", horizon_gains.heading_weight,
                 "receding horizon: metres a radian of heading error counts as");
  app.add_option("--path-weight", horizon_gains.path_weight,
                 "receding horizon: weight of the predicted distance to the path");
  app.add_option("--lookahead", gains.lookahead, "closed loop: lookahead [m]");
  app.add_option("--heading-gain", gains.heading_gain,
                 "closed loop: course error share per period");
  bool with_bound = true;
  app.add_flag("--bound,!--no-bound", with_bound,
               "print the tracking bound of the path beside the result (default on; a few "
               "seconds)");
  app.add_option("--csv", csv_path, "write t, true and estimated head position, command as CSV");
  if (const auto exit_code = flagella::cli::parseArguments(app, argc, argv)) return *exit_code;

  return flagella::cli::runGuarded([&] {
    session_options.camera.seed = session_options.imu.seed + 1;
    const flagella::SimulationConfig config =
        flagella::loadSimulationConfig(config_path, overrides);
    const auto calibration = flagella::control::loadCalibration(calibration_path);
    const auto spec = flagella::control::loadPathSpec(path_path);
    flagella::SimSession session(config, session_options);
    std::unique_ptr<flagella::control::PathControllerBase> controller;
    if (mode == "open_loop")
      controller = std::make_unique<flagella::control::ScheduleController>(spec, calibration);
    else if (mode == "receding_horizon")
      controller = std::make_unique<flagella::control::RecedingHorizonController>(
          spec, calibration, horizon_gains, gains);
    else
      controller =
          std::make_unique<flagella::control::PathFollowingController>(spec, calibration, gains);
    flagella::control::TimedController timed(
        *controller, static_cast<std::size_t>(max_duration * session_options.imu.rate) + 1);
    flagella::control::LcmHarness harness(session, timed, options);

    flagella::control::TrackingStats stats;
    std::ofstream csv;
    if (!csv_path.empty()) {
      csv.open(csv_path);
      if (!csv) throw std::runtime_error("cannot write " + csv_path);
      csv << "time,x,y,cross_track,motor_command,progress,estimated_cross_track,heading_error\n";
    }
    double next_sample = 0.0;
    bool finished = false;
    flagella::LogThrottle progress_line(kProgressPeriod);
    const auto wall_start = std::chrono::steady_clock::now();
    const auto after_step = [&]() {
      const auto& status = controller->status();
      const double wall =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
      long held_back = 0;
      if (wall >= kProgressPeriod && progress_line.allow(wall, held_back))
        std::fprintf(stderr, "flagella_follow_path: t = %.0f s simulated, %.0f %% of the path\n",
                     session.time(), 100.0 * status.progress);
      if (!status.anchored || session.time() + 1e-9 < next_sample) return;
      next_sample += sample_interval;
      const flagella::RodSnapshot s = session.snapshot();
      const flagella::control::Vec2 p(s.head_position.x(), s.head_position.y());
      const double d = controller->worldPath().project(p).distance;
      stats.add(d);
      if (csv) {
        csv << session.time() << "," << p.x() << "," << p.y() << "," << d << ","
            << session.health().motor_applied << "," << status.progress << "," << status.cross_track
            << "," << status.heading_error << "\n";
      }
      if (status.mode_finished) {
        finished = true;
        harness.requestStop();
      }
    };
    const flagella::control::HarnessReport report = harness.run(max_duration, after_step);
    const double l = config.geometry.tail_length;
    std::printf("%s on %s: %s after %.1f s simulated (%.1f s wall, %.1fx real time)\n",
                controller->name(), spec.description.c_str(),
                finished ? "path complete" : "NOT complete", report.sim_time, report.wall_seconds,
                report.sim_time / report.wall_seconds);
    std::printf(
        "cross-track error of the true head path: max %.1f mm (%.3f l), RMS %.1f mm "
        "(%.3f l), %ld samples\n",
        flagella::units::metresToMm(stats.max_abs), stats.max_abs / l,
        flagella::units::metresToMm(stats.rms()), stats.rms() / l, stats.samples);
    std::printf(
        "controller compute time per step (%zu steps): median %.1f us, 99.9th percentile %.1f "
        "us, max %.2f ms\n",
        timed.steps(), 1e6 * timed.quantile(0.5), 1e6 * timed.quantile(0.999), 1e3 * timed.max());
    if (with_bound && controller->status().anchored) {
      // docs/model.md 7.5: the best any switching schedule does on the calibrated model
      const flagella::control::TrackingBound bound =
          flagella::control::computeTrackingBound(controller->worldPath(), spec.laps, calibration);
      std::printf("%s; result / bound: max %.2f, RMS %.2f\n",
                  flagella::control::describeBound(bound, l).c_str(),
                  stats.max_abs / bound.best_max.max_error, stats.rms() / bound.best_rms.rms_error);
    }
    return report.halted ? 3 : finished ? 0 : 4;
  });
}
