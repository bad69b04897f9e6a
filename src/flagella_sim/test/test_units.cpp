// flagella::units against independent truth: 60 rpm is one turn per second, 180 deg is pi,
// 1 m is 1000 mm, and the conversions are usable in constant expressions.
#include <gtest/gtest.h>

#include <cmath>
#include <initializer_list>

#include "flagella_sim/core/units.h"

namespace flagella::units {
namespace {

const double kTruePi = std::acos(-1.0);  // independent of units::pi

static_assert(rpmToRadPerSec(60.0) > 6.2831 && rpmToRadPerSec(60.0) < 6.2832);
static_assert(radPerSecToRpm(kRadPerSecPerRpm) > 0.999999 &&
              radPerSecToRpm(kRadPerSecPerRpm) < 1.000001);
static_assert(degToRad(180.0) > 3.14159 && degToRad(180.0) < 3.1416);
static_assert(radToDeg(pi) == 180.0);
static_assert(metresToMm(1.0) == 1000.0 && mmToMetres(1000.0) == 1.0);
static_assert(kSecondsPerHour == 60.0 * 60.0);

TEST(Units, Pi) {
  EXPECT_EQ(pi, kTruePi);
  EXPECT_EQ(pi, M_PI);
}

TEST(Units, RpmAndRadPerSec) {
  EXPECT_NEAR(rpmToRadPerSec(60.0), 2.0 * kTruePi, 1e-15);  // one turn per second
  EXPECT_NEAR(rpmToRadPerSec(-30.0), -kTruePi, 1e-15);
  EXPECT_NEAR(radPerSecToRpm(2.0 * kTruePi), 60.0, 1e-13);
  EXPECT_NEAR(kRadPerSecPerRpm * kRpmPerRadPerSec, 1.0, 1e-15);
  for (double rpm : {-250.0, 0.5, 43.27, 1e5}) {
    EXPECT_NEAR(radPerSecToRpm(rpmToRadPerSec(rpm)), rpm, 1e-14 * std::abs(rpm));
    // the forms the code used before this header
    EXPECT_NEAR(rpmToRadPerSec(rpm), rpm * 2.0 * M_PI / 60.0, 1e-15 * std::abs(rpm));
  }
}

TEST(Units, DegreesAndRadians) {
  EXPECT_NEAR(degToRad(180.0), kTruePi, 1e-15);
  EXPECT_NEAR(degToRad(-90.0), -kTruePi / 2.0, 1e-15);
  EXPECT_NEAR(radToDeg(kTruePi / 4.0), 45.0, 1e-13);
  for (double deg : {-360.0, 3.0, 179.0})
    EXPECT_NEAR(radToDeg(degToRad(deg)), deg, 1e-14 * std::abs(deg));
}

TEST(Units, MetresAndMillimetres) {
  EXPECT_EQ(metresToMm(1.0), 1000.0);
  EXPECT_DOUBLE_EQ(metresToMm(0.111), 111.0);
  EXPECT_DOUBLE_EQ(mmToMetres(0.3), 0.0003);
  for (double m : {-2.5, 4.11e-3, 10.0}) EXPECT_DOUBLE_EQ(mmToMetres(metresToMm(m)), m);
}

}  // namespace
}  // namespace flagella::units
