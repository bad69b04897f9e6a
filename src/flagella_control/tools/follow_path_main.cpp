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
#include <ostream>

#include "flagella_control/lcm_harness.h"
#include "flagella_control/path_controller_factory.h"
#include "flagella_control/timed_controller.h"
#include "flagella_control/tracking_bound_report.h"
#include "flagella_control/tracking_metrics.h"
#include "flagella_sim/core/parameter_set.h"
#include "flagella_sim/core/units.h"
#include "flagella_sim/runtime/log_throttle.h"
#include "flagella_sim/runtime/tool_main.h"
#include "flagella_sim/simulation/simulation_config.h"

namespace {

namespace fc = flagella::control;

constexpr double kProgressPeriod = 10.0;  // [s wall] between progress lines on stderr

/// The command line.
struct Arguments {
  std::string config_path, calibration_path, path_path, csv_path;
  std::vector<std::string> overrides;
  double max_duration = 3000.0, sample_interval = 0.5;
  bool with_bound = true;
  fc::HarnessOptions harness;
  fc::PathControllerOptions controller;
  flagella::SessionOptions session;
  Arguments() { session.initial_motor = "stopped"; }
};

void addOptions(CLI::App& app, Arguments& a) {
  app.add_option("config", a.config_path, "robot config YAML")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("--calibration", a.calibration_path, "calibration YAML (flagella_calibrate)")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("--path", a.path_path, "path YAML (config/paths)")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("--mode", a.controller.mode, "receding_horizon, closed_loop or open_loop")
      ->check(CLI::IsMember(fc::pathControllerModes()));
  app.add_option("--set", a.overrides,
                 "config override a.b=value (repeatable), e.g. a model error");
  app.add_option("--max-duration", a.max_duration, "give up after this many simulated seconds")
      ->check(CLI::PositiveNumber);
  app.add_option("--imu-orientation-noise", a.session.imu.orientation_noise_std,
                 "IMU orientation noise std [rad]");
  app.add_option("--imu-gyro-noise", a.session.imu.gyro_noise_std, "gyro noise std [rad/s]");
  app.add_option("--camera-rate", a.session.camera.rate, "camera fixes per second [Hz]");
  app.add_option("--camera-noise", a.session.camera.noise_std, "camera noise std [m]");
  app.add_option("--seed", a.session.imu.seed, "noise seed (IMU; camera uses seed + 1)");
  fc::RecedingHorizonGains& horizon = a.controller.horizon_gains;
  app.add_option("--horizon", horizon.horizon,
                 "receding horizon: switching periods looked ahead (1..3)");
  app.add_option("--heading-weight", horizon.heading_weight,
                 "receding horizon: metres a radian of heading error counts as");
  app.add_option("--path-weight", horizon.path_weight,
                 "receding horizon: weight of the predicted distance to the path");
  app.add_option("--lookahead", a.controller.gains.lookahead, "closed loop: lookahead [m]");
  app.add_option("--heading-gain", a.controller.gains.heading_gain,
                 "closed loop: course error share per period");
  app.add_flag("--bound,!--no-bound", a.with_bound,
               "print the tracking bound of the path beside the result (default on; a few "
               "seconds)");
  app.add_option("--csv", a.csv_path, "write t, true and estimated head position, command as CSV");
}

/// Samples the true head path every `interval` simulated seconds once the path is anchored:
/// cross-track statistics and CSV rows; prints a progress line every kProgressPeriod wall s.
class PathSampler {
 public:
  PathSampler(const flagella::SimSession& session, const fc::PathControllerBase& controller,
              double interval, std::ostream* csv)
      : session_(session),
        controller_(controller),
        interval_(interval),
        csv_(csv),
        progress_line_(kProgressPeriod),
        wall_start_(std::chrono::steady_clock::now()) {}

  /// After each controller step; true once the controller reports the run finished (at a sample).
  bool afterStep() {
    const auto& status = controller_.status();
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start_).count();
    long held_back = 0;
    if (wall >= kProgressPeriod && progress_line_.allow(wall, held_back))
      std::fprintf(stderr, "flagella_follow_path: t = %.0f s simulated, %.0f %% of the path\n",
                   session_.time(), 100.0 * status.progress);
    if (!status.anchored || session_.time() + 1e-9 < next_sample_) return false;
    next_sample_ += interval_;
    const flagella::RodSnapshot s = session_.snapshot();
    const fc::Vec2 p(s.head_position.x(), s.head_position.y());
    const double d = controller_.worldPath().project(p).distance;
    stats_.add(d);
    if (csv_) {
      *csv_ << session_.time() << "," << p.x() << "," << p.y() << "," << d << ","
            << session_.health().motor_applied << "," << status.progress << ","
            << status.cross_track << "," << status.heading_error << "\n";
    }
    return status.mode_finished;
  }
  const fc::TrackingStats& stats() const { return stats_; }

 private:
  const flagella::SimSession& session_;
  const fc::PathControllerBase& controller_;
  double interval_;
  std::ostream* csv_;
  flagella::LogThrottle progress_line_;
  std::chrono::steady_clock::time_point wall_start_;
  double next_sample_ = 0.0;
  fc::TrackingStats stats_;
};

/// The result lines: completion, cross-track error, compute time and (with_bound) the bound.
void printResult(const Arguments& a, const flagella::SimulationConfig& config,
                 const fc::PathSpec& spec, const fc::BinaryCalibration& calibration,
                 const fc::PathControllerBase& controller, const fc::TimedController& timed,
                 const fc::HarnessReport& report, const fc::TrackingStats& stats, bool finished) {
  const double l = config.robot->filamentLength();
  std::printf("%s on %s: %s after %.1f s simulated (%.1f s wall, %.1fx real time)\n",
              controller.name(), spec.description.c_str(),
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
  if (a.with_bound && controller.status().anchored) {
    // docs/model.md 7.5: the best any switching schedule does on the calibrated model
    const fc::TrackingBound bound =
        fc::computeTrackingBound(controller.worldPath(), spec.laps, calibration);
    std::printf("%s; result / bound: max %.2f, RMS %.2f\n", fc::describeBound(bound, l).c_str(),
                stats.max_abs / bound.best_max.max_error, stats.rms() / bound.best_rms.rms_error);
  }
}

/// Runs the path to its end or max_duration; the exit code (0 complete, 3 halted, 4 not done).
int followPath(Arguments& a) {
  a.session.camera.seed = a.session.imu.seed + 1;
  const flagella::SimulationConfig config =
      flagella::loadSimulationConfig(a.config_path, a.overrides);
  const auto calibration = fc::loadCalibration(a.calibration_path);
  const auto spec = fc::loadPathSpec(a.path_path);
  flagella::SimSession session(config, a.session);
  const std::unique_ptr<fc::PathControllerBase> controller =
      fc::makePathController(spec, calibration, a.controller);
  fc::TimedController timed(*controller,
                            static_cast<std::size_t>(a.max_duration * a.session.imu.rate) + 1);
  fc::LcmHarness harness(session, timed, a.harness);

  std::ofstream csv;
  if (!a.csv_path.empty()) {
    csv.open(a.csv_path);
    if (!csv) throw std::runtime_error("cannot write " + a.csv_path);
    csv << "time,x,y,cross_track,motor_command,progress,estimated_cross_track,heading_error\n";
  }
  PathSampler sampler(session, *controller, a.sample_interval, a.csv_path.empty() ? nullptr : &csv);
  bool finished = false;
  const fc::HarnessReport report = harness.run(a.max_duration, [&] {
    if (!sampler.afterStep()) return;
    finished = true;
    harness.requestStop();
  });
  printResult(a, config, spec, calibration, *controller, timed, report, sampler.stats(), finished);
  return report.halted ? 3 : finished ? 0 : 4;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Path following over LCM: core simulator + controller core (no ROS)"};
  Arguments arguments;
  addOptions(app, arguments);
  if (const auto exit_code = flagella::cli::parseArguments(app, argc, argv)) return *exit_code;
  return flagella::cli::runGuarded([&] { return followPath(arguments); });
}
