// Headless over LCM (memq://, no ROS master): the closed-loop controller cores drive the core
// simulator of the interface robot around the square of config/paths/square.yaml, with IMU and
// camera noise. The true head path must complete the lap and stay near the reference; the
// receding-horizon core near the path's tracking bound.
#include <gtest/gtest.h>

#include <cstdio>
#include <functional>
#include <string>

#include "flagella_control/lcm_harness.h"
#include "flagella_control/path_controllers.h"
#include "flagella_control/receding_horizon_controller.h"
#include "flagella_control/tracking_bound.h"
#include "flagella_control/tracking_metrics.h"
#include "flagella_sim/core/units.h"
#include "flagella_sim/simulation/simulation_config.h"

namespace fc = flagella::control;
namespace units = flagella::units;

namespace {

struct SquareRun {
  fc::TrackingStats stats;
  bool finished = false, halted = false;
  double estimate_error = 0.0;  ///< max |estimated - true position| [m]
  double time = 0.0;            ///< simulated [s]
};

/// The main job's sensors (IMU orientation 0.01 rad, gyro 0.005 rad/s, camera 2 Hz with 2 mm).
SquareRun followSquare(const flagella::SimulationConfig& config,
                       const std::function<fc::PathControllerBase&()>& make_controller,
                       const std::function<fc::Vec2()>& estimate) {
  flagella::SessionOptions options;
  options.initial_motor = "stopped";
  options.imu.orientation_noise_std = 0.01;
  options.imu.gyro_noise_std = 0.005;
  options.camera.rate = 2.0;
  options.camera.noise_std = 0.002;
  flagella::SimSession session(config, options);
  fc::PathControllerBase& controller = make_controller();
  fc::LcmHarness harness(session, controller, fc::HarnessOptions{});
  SquareRun r;
  long steps = 0;
  harness.run(3000.0, [&]() {
    if (!controller.status().anchored || ++steps % 50 != 0) return;  // every 0.5 s
    const flagella::RodSnapshot s = session.snapshot();
    const fc::Vec2 truth(s.head_position.x(), s.head_position.y());
    r.stats.add(controller.worldPath(), truth);
    r.estimate_error = std::max(r.estimate_error, (estimate() - truth).norm());
    if (controller.status().mode_finished) {
      r.finished = true;
      harness.requestStop();
    }
  });
  r.halted = session.halted();
  r.time = session.time();
  const double l = config.robot->filamentLength();
  std::printf(
      "[ lcm path ] %s on the square: %s at t = %.1f s; cross-track max %.1f mm (%.3f l), RMS "
      "%.1f mm (%.3f l); position estimate error max %.1f mm\n",
      controller.name(), r.finished ? "finished" : "NOT finished", r.time,
      units::metresToMm(r.stats.max_abs), r.stats.max_abs / l, units::metresToMm(r.stats.rms()),
      r.stats.rms() / l, units::metresToMm(r.estimate_error));
  return r;
}

const std::string kDir = FLAGELLA_CONFIG_DIR;

}  // namespace

TEST(LcmPathFollowing, ControllerCoreDrivesTheSimulatorAroundASquare) {
  const auto config = flagella::loadSimulationConfig(kDir + "/interface_path_planning.yaml", {});
  const auto calibration = fc::loadCalibration(kDir + "/calibration/interface_path_planning.yaml");
  const auto spec = fc::loadPathSpec(kDir + "/paths/square.yaml");
  fc::PathFollowingController controller(spec, calibration);
  const SquareRun r = followSquare(
      config, [&]() -> fc::PathControllerBase& { return controller; },
      [&]() { return controller.estimatedPosition(); });
  const double l = config.robot->filamentLength();
  EXPECT_TRUE(r.finished);
  EXPECT_FALSE(r.halted);
  // The square's side is 0.3 m = 2.7 l; the robot turns on a circle of about 1 l, so corners
  // are cut: the bound is 0.7 l (as in the rostest path_following_square of this controller).
  EXPECT_LT(r.stats.max_abs / l, 0.7);
  // The camera-corrected estimate stays close to the truth (noise 2 mm, fixes at 2 Hz).
  EXPECT_LT(r.estimate_error, 0.01);
  // A lap of 1.2 m at about 1.2 mm/s: it cannot have finished before 800 s of advance... loosely.
  EXPECT_GT(r.time, 0.5 * spec.path.length() / calibration.advanceSpeed());
}

TEST(LcmPathFollowing, RecedingHorizonNearTheTrackingBound) {
  const auto config = flagella::loadSimulationConfig(kDir + "/interface_path_planning.yaml", {});
  const auto calibration = fc::loadCalibration(kDir + "/calibration/interface_path_planning.yaml");
  const auto spec = fc::loadPathSpec(kDir + "/paths/square.yaml");
  fc::RecedingHorizonController controller(spec, calibration);
  const SquareRun r = followSquare(
      config, [&]() -> fc::PathControllerBase& { return controller; },
      [&]() { return controller.estimatedPosition(); });
  const fc::TrackingBound& bound = controller.bound();
  ASSERT_TRUE(bound.best_max.complete);
  std::printf(
      "[ lcm path ] tracking bound: max %.1f mm, RMS %.1f mm; %ld planned periods, %ld "
      "fallback\n",
      units::metresToMm(bound.best_max.max_error), units::metresToMm(bound.best_rms.rms_error),
      controller.plannedPeriods(), controller.fallbackPeriods());
  EXPECT_TRUE(r.finished);
  EXPECT_FALSE(r.halted);
  EXPECT_LT(r.estimate_error, 0.01);
  // The target with the main job's noise: 1.3x the bound (seed-to-seed the max moves by
  // about 10 %: 1.5x here), RMS 1.3x.
  EXPECT_LT(r.stats.max_abs, 1.5 * bound.best_max.max_error);
  EXPECT_LT(r.stats.rms(), 1.3 * bound.best_rms.rms_error);
  // It followed the plan: fallback periods are the exception.
  EXPECT_LT(controller.fallbackPeriods(), controller.plannedPeriods() / 10 + 1);
}
