// The slider response table (steering_response_tables.h) on a coarse source robot: the gravity
// couple of a COM-COV offset is linear in the offset (docs/model.md 5), so from level cruise the
// initial pitch rate is odd and linear in the slider's offset from park; a larger offset flips
// the head sooner, and the opposite offset brings it back through level. Bad table options are
// named.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "flagella_control/steering_response_tables.h"
#include "support/temp_dir.h"

namespace fc = flagella::control;

namespace {

flagella::SimulationConfig coarseSourceRobot() {
  // edges of 15 mm (23 nodes): the coarse model of the helical calibration test
  return flagella::loadSimulationConfig(
      std::string(FLAGELLA_CONFIG_DIR) + "/helical_steering_source.yaml",
      {"robot.edge_length=0.015"});
}

TEST(SteeringTables, PitchRateIsOddAndLinearInTheSliderOffset) {
  const flagella::SimulationConfig config = coarseSourceRobot();
  fc::SteeringCalibration c;
  c.buckling_threshold = 7.0;  // [rad/s], about 67 rpm: only the cruise is used here
  c.cruise_omega = 4.2;
  c.slider_min = config.slider.travel_min;
  c.slider_max = config.slider.travel_max;
  c.park_position = config.slider.initial_position;  // the config parks it at l = 0
  fc::SteeringCalibrationOptions options;
  options.settle_time = 5.0;
  options.pitch_window = 2.0;
  fc::SteeringTableOptions table;
  const double d = 1e-3;
  table.slider_offsets = {d, -d, 2 * d};
  table.flip_elevation = 45.0 * M_PI / 180.0;
  table.flip_timeout = 80.0;
  const auto rows = fc::measureSliderTable(config, c, table, options);
  ASSERT_EQ(rows.size(), 3u);
  const double up = rows[0].pitch_rate, down = rows[1].pitch_rate, twice = rows[2].pitch_rate;
  RecordProperty("pitch_rate_deg_s", std::to_string(up * 180 / M_PI));
  EXPECT_GT(std::abs(up), 0.2 * M_PI / 180);  // a couple that pitches by tenths of deg/s at least
  EXPECT_NEAR(down, -up, 0.1 * std::abs(up));
  EXPECT_NEAR(twice, 2.0 * up, 0.15 * std::abs(up));
  // The larger couple flips the head sooner; each flipped head comes back through level.
  ASSERT_GT(rows[0].flip_time, 0.0);
  ASSERT_GT(rows[2].flip_time, 0.0);
  EXPECT_LT(rows[2].flip_time, rows[0].flip_time);
  EXPECT_GT(rows[0].return_time, 0.0);
  // Held off level the axis's azimuth precesses. Turned by pi about the direction of travel, the
  // neutrally buoyant robot with the opposite offset is the same robot with gravity's couple
  // unchanged: its elevation and its azimuth rate change sign, so the rates are odd in the offset.
  const double az_up = rows[0].azimuth_rate, az_down = rows[1].azimuth_rate;
  RecordProperty("azimuth_rate_deg_s", std::to_string(az_up * 180 / M_PI));
  EXPECT_GT(std::abs(az_up), 0.2 * M_PI / 180);
  EXPECT_NEAR(az_down, -az_up, 0.1 * std::abs(az_up));
  // So are the azimuth's turns over the hold and over the return (the opposite offset).
  EXPECT_GT(std::abs(rows[0].hold_turn), 0.1);
  EXPECT_NEAR(rows[1].hold_turn, -rows[0].hold_turn, 0.1 * std::abs(rows[0].hold_turn));
  EXPECT_NEAR(rows[1].return_turn, -rows[0].return_turn, 0.1 * std::abs(rows[0].return_turn));
  for (const auto& r : rows) EXPECT_GT(r.return_time, 0.0);  // every row comes back level
  // The hold of a flipped row ends at the flip: its last window rises toward flip_elevation.
  for (const auto& r : {rows[0], rows[2]}) {
    EXPECT_GT(r.end_elevation, 0.0);
    EXPECT_LT(r.end_elevation, table.flip_elevation);
    EXPECT_GT(r.end_elevation_rate, 0.0);
  }
  flagella::testing::TempDir dir;
  fc::writeSliderTable(rows, (dir.path() / "slider.csv").string());
  std::ifstream in((dir.path() / "slider.csv").string());
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header,
            "offset_mm,pitch_rate_deg_s,flip_time_s,return_time_s,end_elevation_deg,"
            "end_elevation_rate_deg_s,azimuth_rate_deg_s,hold_turn_deg,return_turn_deg");
}

// The held attitude's window against a closed form: an axis whose azimuth turns at a constant
// rate through +-pi (unwrapped) while its elevation rises linearly; samples older than the
// window (a first stretch turning the other way) are dropped.
TEST(SteeringTables, HeldAttitudeWindowFitsLinearRatesAcrossTheAzimuthWrap) {
  fc::HeldAttitudeWindow window(10.0);
  const double dt = 0.01, rate = -0.7, e0 = 0.3, e_rate = 0.01;
  const auto direction = [](double azimuth, double elevation) {
    return fc::directionFrom(azimuth, elevation);
  };
  for (int k = 0; k <= 1000; ++k)  // t = 0..10 s: azimuth turning left, to be dropped
    window.add(k * dt, direction(2.5 + 0.4 * k * dt, e0));
  const double start = 2.5 + 0.4 * 10.0;
  for (int k = 1; k <= 2000; ++k) {  // t = 10..30 s: right at 0.7 rad/s, through -pi several times
    const double t = 10.0 + k * dt;
    window.add(t, direction(start + rate * (t - 10.0), e0 + e_rate * (t - 10.0)));
  }
  double elevation = 0, elevation_rate = 0, azimuth_rate = 0;
  window.fit(elevation, elevation_rate, azimuth_rate);
  EXPECT_NEAR(azimuth_rate, rate, 1e-9);
  EXPECT_NEAR(elevation_rate, e_rate, 1e-9);
  EXPECT_NEAR(elevation, e0 + e_rate * 15.0, 1e-3);                     // mean over t = 20..30 s
  EXPECT_NEAR(window.azimuthChange(), 0.4 * 10.0 + rate * 20.0, 1e-9);  // from the first sample
  fc::HeldAttitudeWindow empty(10.0);
  empty.fit(elevation, elevation_rate, azimuth_rate);
  EXPECT_EQ(azimuth_rate, 0.0);
}

TEST(SteeringTables, BadOptionsAreNamed) {
  fc::SteeringTableOptions t;
  t.slider_offsets = {0.0};
  EXPECT_THROW(t.validate(), std::invalid_argument);
  t.slider_offsets = {1e-3};
  t.pulse_factors = {0.9};
  t.pulse_durations = {2.0};
  try {
    t.validate();
    FAIL() << "a pulse below the threshold was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("pulse_factors"), std::string::npos) << e.what();
  }
  t.pulse_factors = {2.0};
  t.pulse_durations = {};
  EXPECT_THROW(t.validate(), std::invalid_argument);
  t.pulse_factors = {};
  t.hold_window = 0.0;
  try {
    t.validate();
    FAIL() << "a hold window of 0 s was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("hold_window"), std::string::npos) << e.what();
  }
}

}  // namespace
