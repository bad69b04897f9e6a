// Headless over LCM (memq://, no ROS master): the closed-loop controller core drives the core
// simulator of the interface robot around the square of config/paths/square.yaml, with IMU and
// camera noise. The true head path must complete the lap and stay near the reference.
#include <gtest/gtest.h>

#include <cstdio>

#include "flagella_control/lcm_harness.h"
#include "flagella_control/path_controllers.h"
#include "flagella_control/tracking_metrics.h"
#include "flagella_sim/core/units.h"
#include "flagella_sim/simulation/simulation_config.h"

namespace fc = flagella::control;
namespace units = flagella::units;

TEST(LcmPathFollowing, ControllerCoreDrivesTheSimulatorAroundASquare) {
  const std::string dir = FLAGELLA_CONFIG_DIR;
  const auto config = flagella::loadSimulationConfig(dir + "/interface_path_planning.yaml", {});
  const auto calibration = fc::loadCalibration(dir + "/calibration/interface_path_planning.yaml");
  const auto spec = fc::loadPathSpec(dir + "/paths/square.yaml");
  flagella::SessionOptions options;
  options.initial_motor = "stopped";
  options.imu.orientation_noise_std = 0.01;
  options.imu.gyro_noise_std = 0.005;
  options.camera.rate = 2.0;
  options.camera.noise_std = 0.002;
  flagella::SimSession session(config, options);
  fc::PathFollowingController controller(spec, calibration);
  fc::LcmHarness harness(session, controller, fc::HarnessOptions{});

  fc::TrackingStats stats;
  bool finished = false;
  double estimate_error = 0.0;
  long steps = 0;
  harness.run(3000.0, [&]() {
    if (!controller.status().anchored || ++steps % 50 != 0) return;  // every 0.5 s
    const flagella::RodSnapshot s = session.snapshot();
    const fc::Vec2 truth(s.head_position.x(), s.head_position.y());
    stats.add(controller.worldPath(), truth);
    estimate_error = std::max(estimate_error, (controller.estimatedPosition() - truth).norm());
    if (controller.status().mode_finished) {
      finished = true;
      harness.requestStop();
    }
  });
  const double l = config.geometry.tail_length;
  std::printf(
      "[ lcm path ] square: %s at t = %.1f s; cross-track max %.1f mm (%.3f l), RMS %.1f mm "
      "(%.3f l); position estimate error max %.1f mm\n",
      finished ? "finished" : "NOT finished", session.time(), units::metresToMm(stats.max_abs),
      stats.max_abs / l, units::metresToMm(stats.rms()), stats.rms() / l,
      units::metresToMm(estimate_error));
  EXPECT_TRUE(finished);
  EXPECT_FALSE(session.halted());
  // The square's side is 0.3 m = 2.7 l; the robot turns on a circle of about 1 l, so corners
  // are cut: the bound is 0.7 l (as in the rostest path_following_square).
  EXPECT_LT(stats.max_abs / l, 0.7);
  // The camera-corrected estimate stays close to the truth (noise 2 mm, fixes at 2 Hz).
  EXPECT_LT(estimate_error, 0.01);
  // A lap of 1.2 m at about 1.2 mm/s: it cannot have finished before 800 s of advance... loosely.
  EXPECT_GT(session.time(), 0.5 * spec.path.length() / calibration.advanceSpeed());
}
