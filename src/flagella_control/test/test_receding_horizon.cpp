// The receding-horizon path follower (receding_horizon_controller.h) in closed loop with the
// ideal kinematic plant (support/kinematic_plant.h): against the tracking bound of the plant it
// drives (tracking_bound.h), against the line-of-sight controller, with a wrong yaw rate in the
// calibration, and its errors.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "flagella_control/receding_horizon_controller.h"
#include "flagella_control/tracking_bound.h"
#include "support/kinematic_plant.h"

using namespace flagella::control::testing;  // NOLINT: the plant and its helpers

namespace {

struct Outcome {
  Result horizon, line_of_sight;
  fc::TrackingBound bound;  ///< of the plant as it really is
  double response_scale = 1.0;
};

/// The square on the plant whose yaw rates and sideways velocities are `scale` times the
/// calibration's (a lateral-force error: the simulator's C_yr does this, README), camera noise.
Outcome followSquare(double scale) {
  const fc::BinaryCalibration c = nominalCalibration();
  Scenario sc;
  sc.plus_scale = sc.minus_scale = sc.sideways_scale = scale;
  sc.camera_noise = 0.002;  // the main job's camera
  sc.after_finish = 1.0;
  Outcome o;
  fc::RecedingHorizonController horizon(startFrameRectangle(), c);
  o.horizon = run(horizon, c, sc);
  o.response_scale = horizon.responseScale();
  fc::PathFollowingController line_of_sight(startFrameRectangle(), c);
  o.line_of_sight = run(line_of_sight, c, sc);
  o.bound = fc::computeTrackingBound(horizon.worldPath(), 1, plantCalibration(scale));
  print("receding horizon", o.horizon);
  print("line of sight", o.line_of_sight);
  std::printf("[ control  ] bound of the plant: max %.1f mm, RMS %.1f mm; response scale %.3f\n",
              1e3 * o.bound.best_max.max_error, 1e3 * o.bound.best_rms.rms_error, o.response_scale);
  return o;
}

}  // namespace

TEST(RecedingHorizon, NearTheBoundOnTheNominalPlant) {
  const Outcome o = followSquare(1.0);
  ASSERT_TRUE(o.horizon.finished);
  ASSERT_TRUE(o.bound.best_max.complete);
  // The targets with the main job's camera noise: at most 1.3x the bound.
  EXPECT_LE(o.horizon.max_ct, 1.3 * o.bound.best_max.max_error);
  EXPECT_LE(o.horizon.rms_ct, 1.3 * o.bound.best_rms.rms_error);
  // Never below what no schedule can beat by much (sampled 100x more often than the bound).
  EXPECT_GE(o.horizon.max_ct, 0.8 * o.bound.best_max.max_error);
  EXPECT_LT(o.horizon.max_ct, o.line_of_sight.max_ct);
  EXPECT_LT(o.horizon.rms_ct, o.line_of_sight.rms_ct);
  EXPECT_NEAR(o.response_scale, 1.0, 0.05);
}

TEST(RecedingHorizon, AdaptsToALateralResponse30PercentLow) {
  const Outcome o = followSquare(0.7);
  ASSERT_TRUE(o.horizon.finished);
  ASSERT_TRUE(o.bound.best_max.complete);
  EXPECT_LE(o.horizon.max_ct, 1.6 * o.bound.best_max.max_error);
  EXPECT_LE(o.horizon.rms_ct, 1.6 * o.bound.best_rms.rms_error);
  EXPECT_LT(o.horizon.max_ct, o.line_of_sight.max_ct);
  // The IMU's turns show the responses 30 % low.
  EXPECT_NEAR(o.response_scale, 0.7, 0.07);
}

TEST(RecedingHorizon, InvalidGainsThrowNamingTheField) {
  const auto message = [](fc::RecedingHorizonGains g) {
    try {
      fc::RecedingHorizonController(startFramePolyline(), nominalCalibration(), g);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  fc::RecedingHorizonGains g;
  g.horizon = 4;
  EXPECT_NE(message(g).find("horizon"), std::string::npos) << message(g);
  g = {};
  g.fallback_distance = 0.0;
  EXPECT_NE(message(g).find("fallback_distance"), std::string::npos) << message(g);
  g = {};
  g.adaptation_forgetting = NAN;
  EXPECT_NE(message(g).find("adaptation_forgetting"), std::string::npos) << message(g);
  g = {};
  g.path_weight = -1.0;
  EXPECT_NE(message(g).find("path_weight"), std::string::npos) << message(g);
  EXPECT_EQ(message({}), "");
}
