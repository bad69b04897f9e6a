// The ADXL345-like accelerometer (runtime/accelerometer.h): head tilt recovered from a known head
// orientation under gravity alone within the bound the 3.9 mg resolution allows, saturation at
// the selected range, the output data rate, noise and bias statistics, seeding, and errors that
// name the field.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <string>

#include "flagella_sim/core/parameter_set.h"
#include "flagella_sim/runtime/accelerometer.h"
#include "flagella_sim/runtime/imu_model.h"
#include "support/temp_dir.h"

namespace flagella {
namespace {

const Vec3 kGravity(0.0, -9.81, 0.0);  // y up, as the helical configs

// A head whose axis t^0 (head z) has elevation `elevation` above the horizontal, rolled by
// `roll` about itself.
Eigen::Quaterniond headOrientation(double elevation, double roll) {
  // t^0 starts horizontal (world z), is pitched up about world x by `elevation`.
  return Eigen::Quaterniond(Eigen::AngleAxisd(-elevation, Vec3::UnitX()) *
                            Eigen::AngleAxisd(roll, Vec3::UnitZ()));
}

TEST(Accelerometer, TiltFromGravityWithinTheResolution) {
  AccelerometerOptions o;
  o.noise_std = 0.0;
  Accelerometer accel(o);
  // Each axis is off by at most half a count: the direction by at most that over |g|.
  const double half_counts = 0.5 * std::sqrt(3.0) * o.resolution;
  const double bound = std::asin(half_counts / (kGravity.norm() - half_counts));
  double worst = 0.0;
  int k = 0;
  for (double elevation = -M_PI / 2; elevation <= M_PI / 2 + 1e-9; elevation += M_PI / 24) {
    for (double roll : {0.0, 0.7, 2.0, -2.9}) {
      HeadMotion truth;
      truth.orientation = headOrientation(elevation, roll);
      ASSERT_NEAR((truth.orientation * Vec3::UnitZ()).y(), std::sin(elevation), 1e-12);
      ASSERT_TRUE(accel.update(0.01 * ++k, specificForceInHead(truth, kGravity)));
      const double measured = headElevationFromAcceleration(accel.reading().acceleration);
      worst = std::max(worst, std::abs(measured - elevation));
      EXPECT_LE(std::abs(measured - elevation), bound) << elevation << " " << roll;
      EXPECT_FALSE(accel.reading().saturated);
    }
  }
  EXPECT_GT(worst, 0.0);  // quantised: not exact
  RecordProperty("worst_tilt_error_deg", std::to_string(worst * 180.0 / M_PI));
}

TEST(Accelerometer, SaturatesAtTheRange) {
  AccelerometerOptions o;
  o.noise_std = 0.0;
  const Vec3 three_g(3.0 * 9.80665, 0.0, -9.80665);
  Accelerometer two_g(o);
  two_g.update(0.0, three_g);
  EXPECT_TRUE(two_g.reading().saturated);
  EXPECT_EQ(two_g.reading().counts.x(), 512);  // 10 bits at +-2 g, 3.9 mg per count
  EXPECT_EQ(two_g.reading().counts.z(), -256);
  o.range_g = 4.0;
  Accelerometer four_g(o);
  four_g.update(0.0, three_g);
  EXPECT_FALSE(four_g.reading().saturated);
  EXPECT_EQ(four_g.reading().counts.x(), static_cast<int>(std::round(3.0 / 3.9e-3)));
}

TEST(Accelerometer, NewOutputsAtTheDataRateHeldBetween) {
  AccelerometerOptions o;
  o.output_rate = 100.0;
  Accelerometer accel(o);
  int outputs = 0;
  double last_time = -1.0;
  for (int k = 0; k < 1000; ++k) {  // 1 kHz for 1 s
    const double t = 1e-3 * k;
    if (accel.update(t, Vec3(0.0, 0.0, 9.81))) {
      ++outputs;
      if (last_time >= 0.0) {
        EXPECT_NEAR(accel.reading().time - last_time, 0.01, 1e-9);
      }
      last_time = accel.reading().time;
    }
    EXPECT_LE(accel.reading().time, t + 1e-12);  // the nominal sample instant
  }
  EXPECT_EQ(outputs, 100);
}

TEST(Accelerometer, NoiseAndBiasStatisticsAndSeeding) {
  AccelerometerOptions o;
  o.noise_std = 0.2;  // about 5 counts
  o.bias = Vec3(0.3, -0.1, 0.0);
  const int n = 4000;
  Accelerometer a(o), b(o);
  o.seed = 2;
  Accelerometer c(o);
  double sum = 0.0, sum_sq = 0.0;
  bool differs = false;
  for (int k = 0; k < n; ++k) {
    const double t = 0.01 * k;
    a.update(t, Vec3::Zero());
    b.update(t, Vec3::Zero());
    c.update(t, Vec3::Zero());
    ASSERT_EQ(a.reading().counts, b.reading().counts);  // same seed, same output
    differs = differs || a.reading().counts != c.reading().counts;
    sum += a.reading().acceleration.x();
    sum_sq += std::pow(a.reading().acceleration.x(), 2);
  }
  EXPECT_TRUE(differs);
  const double mean = sum / n, sd = std::sqrt(sum_sq / n - mean * mean);
  EXPECT_NEAR(mean, 0.3, 4.0 * 0.2 / std::sqrt(n) + 0.5 * o.resolution);
  // quantisation adds resolution^2/12 to the variance
  EXPECT_NEAR(sd, std::sqrt(0.04 + o.resolution * o.resolution / 12.0), 0.1 * 0.2);
}

TEST(Accelerometer, BadOptionsNameTheField) {
  auto message = [](AccelerometerOptions o) {
    return testing::errorMessageOf<ConfigError>([&] { Accelerometer{o}; });
  };
  AccelerometerOptions o;
  o.range_g = 3.0;
  EXPECT_NE(message(o).find("accelerometer.range_g"), std::string::npos);
  o = {};
  o.output_rate = 0.0;
  EXPECT_NE(message(o).find("accelerometer.output_rate"), std::string::npos);
  o = {};
  o.noise_std = -1.0;
  EXPECT_NE(message(o).find("accelerometer.noise_std"), std::string::npos);
  EXPECT_TRUE(std::isnan(headElevationFromAcceleration(Vec3::Zero())));
}

}  // namespace
}  // namespace flagella
