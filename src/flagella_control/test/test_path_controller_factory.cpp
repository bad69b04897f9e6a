// The path-following controller factory (path_controller_factory.h): each mode builds its core.
#include <gtest/gtest.h>

#include <memory>
#include <stdexcept>
#include <string>

#include "flagella_control/path_controller_factory.h"
#include "support/kinematic_plant.h"
#include "support/temp_dir.h"

namespace fc = flagella::control;
using flagella::control::testing::nominalCalibration;
using flagella::control::testing::startFramePolyline;
using flagella::testing::errorMessageOf;

namespace {

std::unique_ptr<fc::PathControllerBase> make(const std::string& mode,
                                             fc::PathControllerOptions options = {}) {
  options.mode = mode;
  return fc::makePathController(startFramePolyline(), nominalCalibration(), options);
}

}  // namespace

TEST(PathControllerFactory, EachModeBuildsItsController) {
  ASSERT_EQ(fc::pathControllerModes().size(), 3u);
  EXPECT_EQ(fc::pathControllerModes().front(), fc::PathControllerOptions{}.mode);  // the default

  const auto open = make("open_loop");
  EXPECT_NE(dynamic_cast<const fc::ScheduleController*>(open.get()), nullptr);
  EXPECT_STREQ(open->name(), "open_loop_schedule");

  const auto closed = make("closed_loop");
  EXPECT_NE(dynamic_cast<const fc::PathFollowingController*>(closed.get()), nullptr);
  EXPECT_STREQ(closed->name(), "closed_loop_path_following");

  const auto horizon = make("receding_horizon");  // plans the path (about a second)
  EXPECT_NE(dynamic_cast<const fc::RecedingHorizonController*>(horizon.get()), nullptr);
  EXPECT_STREQ(horizon->name(), "receding_horizon_path_following");
}

TEST(PathControllerFactory, UnknownModeThrowsNamingTheFieldAndTheKnownModes) {
  const std::string message = errorMessageOf<std::invalid_argument>([] { make("line_of_sight"); });
  EXPECT_EQ(message,
            "mode must be 'receding_horizon', 'closed_loop' or 'open_loop', got 'line_of_sight'");
  // The ROS node names its parameter.
  EXPECT_EQ(
      errorMessageOf<std::invalid_argument>([] { fc::requirePathControllerMode("", "~mode"); }),
      "~mode must be 'receding_horizon', 'closed_loop' or 'open_loop', got ''");
  for (const std::string& mode : fc::pathControllerModes())
    EXPECT_NO_THROW(fc::requirePathControllerMode(mode));
}

TEST(PathControllerFactory, GainsReachTheController) {
  fc::PathControllerOptions options;
  options.gains.lookahead = -0.1;
  EXPECT_NE(errorMessageOf<std::invalid_argument>([&] {
              make("closed_loop", options);
            }).find("lookahead"),
            std::string::npos);
  EXPECT_NO_THROW(make("open_loop", options));  // open loop uses no gains
  options = {};
  options.horizon_gains.horizon = 4;
  EXPECT_NE(errorMessageOf<std::invalid_argument>([&] {
              make("receding_horizon", options);
            }).find("horizon [periods] = 4 is out of range [1, 3]"),
            std::string::npos);
}
