// Tests of the IMU model and the head-motion tracker against closed forms: the noise-free IMU
// reads R^T w and R^T (a - g) (REP-145: +g upward at rest), biases add, noise has the configured
// standard deviation (sample statistics), and finite differences of poses are exact for a
// constant rotation rate and a constant acceleration.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "flagella_sim/core/parameter_set.h"
#include "flagella_sim/runtime/imu_model.h"
#include "support/temp_dir.h"

namespace flagella {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kG = 9.81;  // [m/s^2]
// Rotations and sums of a few O(10) numbers in double precision agree to far better than this.
constexpr double kExactTol = 1e-12;
// Finite differences over one step: exact up to round-off of angle / dt with dt = 0.01.
constexpr double kTrackerTol = 1e-9;
constexpr double kDt = 0.01;  // [s]

constexpr int kSamples = 20000;
// Sample std of N normal draws has relative standard error 1/sqrt(2N) = 0.5%: 3% is 6 of those.
constexpr double kStdRelTol = 0.03;
// The sample mean has standard error sigma/sqrt(N): 4 of those.
constexpr double kMeanSigmas = 4.0;

const Vec3 kGravity(0.0, 0.0, -kG);

Eigen::Quaterniond arbitraryOrientation() {
  return (Eigen::AngleAxisd(0.7, Vec3(1.0, 2.0, 3.0).normalized()) *
          Eigen::AngleAxisd(-1.1, Vec3(0.3, -1.0, 0.2).normalized()))
      .normalized();
}

HeadMotion arbitraryMotion() {
  HeadMotion m;
  m.time = 1.234;
  m.orientation = arbitraryOrientation();
  m.angular_velocity = Vec3(0.4, -1.3, 2.2);
  m.acceleration = Vec3(0.5, -0.2, 3.0);
  return m;
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

double maxAbs(const Vec3& v) { return v.cwiseAbs().maxCoeff(); }

// --------------------------------------------------------------------------------------------
// Noise-free measurement
// --------------------------------------------------------------------------------------------

TEST(ImuModel, NoiseFreeReadsTheMotionInTheHeadFrame) {
  ImuModel imu(ImuOptions{}, kGravity);
  const HeadMotion truth = arbitraryMotion();
  const ImuSample s = imu.measure(truth);
  // Rotating back into the world with the quaternion gives the world quantities.
  EXPECT_LT(maxAbs(truth.orientation * s.angular_velocity - truth.angular_velocity), kExactTol);
  EXPECT_LT(maxAbs(truth.orientation * s.linear_acceleration - (truth.acceleration - kGravity)),
            kExactTol);
  // And the head-frame components are projections on the head axes (columns of R).
  const Eigen::Matrix3d R = truth.orientation.toRotationMatrix();
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(s.angular_velocity[i], R.col(i).dot(truth.angular_velocity), kExactTol);
    EXPECT_NEAR(s.linear_acceleration[i], R.col(i).dot(truth.acceleration - kGravity), kExactTol);
  }
  EXPECT_LT((s.orientation.coeffs() - truth.orientation.coeffs()).cwiseAbs().maxCoeff(), kExactTol);
  EXPECT_EQ(s.time, truth.time);
  EXPECT_EQ(s.orientation_variance, 0.0);
  EXPECT_EQ(s.angular_velocity_variance, 0.0);
  EXPECT_EQ(s.linear_acceleration_variance, 0.0);
}

TEST(ImuModel, AtRestReadsPlusGAlongTheHeadFrameUp) {
  // REP-145: an accelerometer at rest reads +|g| upward (specific force, not gravity).
  for (const Vec3& gravity : {kGravity, Vec3(0.0, -kG, 0.0), Vec3(-3.0, 4.0, -5.0)}) {
    SCOPED_TRACE(gravity.transpose());
    const Vec3 up = -gravity.normalized();
    ImuModel imu(ImuOptions{}, gravity);
    for (const Eigen::Quaterniond& q : {Eigen::Quaterniond::Identity(), arbitraryOrientation()}) {
      HeadMotion rest;
      rest.orientation = q;
      const ImuSample s = imu.measure(rest);
      EXPECT_NEAR(s.linear_acceleration.norm(), gravity.norm(), kExactTol);
      EXPECT_LT(maxAbs(s.linear_acceleration - gravity.norm() * (q.inverse() * up)), kExactTol);
      EXPECT_LT(maxAbs(s.angular_velocity), kExactTol);
    }
  }
  // Identity orientation, z up: the plain REP-145 reading (0, 0, +g).
  ImuModel imu(ImuOptions{}, kGravity);
  const ImuSample s = imu.measure(HeadMotion{});
  EXPECT_LT(maxAbs(s.linear_acceleration - Vec3(0.0, 0.0, kG)), kExactTol);
}

TEST(ImuModel, FreeFallReadsZero) {
  // Equivalence principle: a falling sensor measures no specific force.
  ImuModel imu(ImuOptions{}, kGravity);
  HeadMotion falling = arbitraryMotion();
  falling.acceleration = kGravity;
  EXPECT_LT(maxAbs(imu.measure(falling).linear_acceleration), kExactTol);
}

TEST(ImuModel, BiasesAddExactly) {
  ImuOptions o;
  o.gyro_bias = Vec3(0.01, -0.02, 0.03);
  o.accel_bias = Vec3(-0.4, 0.5, 0.6);
  ImuModel biased(o, kGravity);
  ImuModel clean(ImuOptions{}, kGravity);
  const HeadMotion truth = arbitraryMotion();
  const ImuSample b = biased.measure(truth);
  const ImuSample c = clean.measure(truth);
  EXPECT_LT(maxAbs(b.angular_velocity - c.angular_velocity - o.gyro_bias), kExactTol);
  EXPECT_LT(maxAbs(b.linear_acceleration - c.linear_acceleration - o.accel_bias), kExactTol);
  EXPECT_LT((b.orientation.coeffs() - c.orientation.coeffs()).cwiseAbs().maxCoeff(), kExactTol);
}

// --------------------------------------------------------------------------------------------
// Noise statistics and seeding
// --------------------------------------------------------------------------------------------

struct AxisStats {
  Vec3 mean = Vec3::Zero();
  Vec3 std_dev = Vec3::Zero();
};

AxisStats statsOf(const std::vector<Vec3>& xs) {
  AxisStats s;
  for (const Vec3& x : xs) s.mean += x;
  s.mean /= static_cast<double>(xs.size());
  Vec3 var = Vec3::Zero();
  for (const Vec3& x : xs) var += (x - s.mean).cwiseAbs2();
  s.std_dev = (var / static_cast<double>(xs.size() - 1)).cwiseSqrt();
  return s;
}

void expectNormalStats(const std::vector<Vec3>& xs, const Vec3& mean, double sigma,
                       const char* what) {
  SCOPED_TRACE(what);
  const AxisStats s = statsOf(xs);
  const double mean_tol = kMeanSigmas * sigma / std::sqrt(static_cast<double>(xs.size()));
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(s.mean[i], mean[i], mean_tol) << "axis " << i;
    EXPECT_NEAR(s.std_dev[i], sigma, kStdRelTol * sigma) << "axis " << i;
  }
}

TEST(ImuModel, NoiseHasTheConfiguredStatistics) {
  constexpr double kOrientationSigma = 0.01;  // [rad]
  constexpr double kGyroSigma = 0.05;         // [rad/s]
  constexpr double kAccelSigma = 0.2;         // [m/s^2]
  ImuOptions o;
  o.orientation_noise_std = kOrientationSigma;
  o.gyro_noise_std = kGyroSigma;
  o.accel_noise_std = kAccelSigma;
  o.gyro_bias = Vec3(0.01, -0.02, 0.03);
  o.accel_bias = Vec3(-0.4, 0.5, 0.6);
  o.seed = 12345;
  ImuModel imu(o, kGravity);
  const HeadMotion truth = arbitraryMotion();
  const Eigen::Matrix3d R = truth.orientation.toRotationMatrix();
  const Vec3 true_gyro = R.transpose() * truth.angular_velocity;
  const Vec3 true_accel = R.transpose() * (truth.acceleration - kGravity);

  std::vector<Vec3> gyro_err, accel_err, tilt;
  for (int k = 0; k < kSamples; ++k) {
    const ImuSample s = imu.measure(truth);
    gyro_err.push_back(s.angular_velocity - true_gyro);
    accel_err.push_back(s.linear_acceleration - true_accel);
    // Orientation error as a rotation vector in the head frame: q_true^-1 q_measured.
    const Eigen::AngleAxisd e(truth.orientation.inverse() * s.orientation);
    tilt.push_back(e.angle() * e.axis());
    ASSERT_DOUBLE_EQ(s.orientation_variance, kOrientationSigma * kOrientationSigma);
    ASSERT_DOUBLE_EQ(s.angular_velocity_variance, kGyroSigma * kGyroSigma);
    ASSERT_DOUBLE_EQ(s.linear_acceleration_variance, kAccelSigma * kAccelSigma);
  }
  expectNormalStats(gyro_err, o.gyro_bias, kGyroSigma, "gyro");
  expectNormalStats(accel_err, o.accel_bias, kAccelSigma, "accelerometer");
  expectNormalStats(tilt, Vec3::Zero(), kOrientationSigma, "orientation");
}

TEST(ImuModel, SameSeedSameSequenceDifferentSeedDifferent) {
  constexpr int kShort = 100;
  ImuOptions o;
  o.orientation_noise_std = 0.01;
  o.gyro_noise_std = 0.05;
  o.accel_noise_std = 0.2;
  o.seed = 7;
  ImuModel a(o, kGravity), b(o, kGravity);
  o.seed = 8;
  ImuModel c(o, kGravity);
  const HeadMotion truth = arbitraryMotion();
  int differing = 0;
  for (int k = 0; k < kShort; ++k) {
    const ImuSample sa = a.measure(truth), sb = b.measure(truth), sc = c.measure(truth);
    ASSERT_EQ(sa.angular_velocity, sb.angular_velocity) << k;
    ASSERT_EQ(sa.linear_acceleration, sb.linear_acceleration) << k;
    ASSERT_EQ(sa.orientation.coeffs(), sb.orientation.coeffs()) << k;
    differing += sa.angular_velocity != sc.angular_velocity &&
                 sa.linear_acceleration != sc.linear_acceleration &&
                 sa.orientation.coeffs() != sc.orientation.coeffs();
  }
  EXPECT_EQ(differing, kShort);
}

// --------------------------------------------------------------------------------------------
// HeadMotionTracker
// --------------------------------------------------------------------------------------------

constexpr double kSpinRate = 3.0;  // [rad/s]
constexpr double kStartTime = 0.37;
constexpr int kTrackerSteps = 400;  // 4 s: the angle passes 2 pi twice (quaternion sign flips)

TEST(HeadMotionTracker, NoMotionBeforeTheSecondUpdate) {
  HeadMotionTracker tracker;
  EXPECT_EQ(tracker.motion().angular_velocity, Vec3::Zero());
  const Eigen::Quaterniond q = arbitraryOrientation();
  tracker.update(kStartTime, q, Vec3(1.0, 2.0, 3.0));
  const HeadMotion m = tracker.motion();
  EXPECT_EQ(m.time, kStartTime);
  EXPECT_EQ(m.orientation.coeffs(), q.coeffs());
  EXPECT_EQ(m.angular_velocity, Vec3::Zero());
  EXPECT_EQ(m.acceleration, Vec3::Zero());
  // clear() forgets the previous pose: again no motion after one update.
  tracker.update(kStartTime + kDt, q, Vec3(5.0, 2.0, 3.0));
  ASSERT_NE(tracker.motion().acceleration, Vec3::Zero());
  tracker.clear();
  tracker.update(kStartTime + 2.0 * kDt, q, Vec3(9.0, 2.0, 3.0));
  EXPECT_EQ(tracker.motion().acceleration, Vec3::Zero());
}

// Constant rotation rate about a fixed axis (world axis: q(t) = R(w t) q0; body axis:
// q(t) = q0 R(w t)); the world angular velocity is w * axis resp. w * R0 axis.
void expectConstantSpinRecovered(const Vec3& axis, double rate, bool body_axis, bool flip_signs) {
  SCOPED_TRACE(::testing::Message()
               << "axis " << axis.transpose() << " rate " << rate
               << (body_axis ? " body" : " world") << (flip_signs ? " flipped signs" : ""));
  const Eigen::Quaterniond q0 = arbitraryOrientation();
  const Vec3 expected = rate * (body_axis ? Vec3(q0 * axis) : axis);
  const Vec3 v0(0.1, -0.2, 0.3), accel(-1.5, 0.25, 4.0);
  HeadMotionTracker tracker;
  for (int k = 0; k <= kTrackerSteps; ++k) {
    const double t = kStartTime + k * kDt;
    const Eigen::AngleAxisd turn(rate * (t - kStartTime), axis);
    Eigen::Quaterniond q =
        body_axis ? Eigen::Quaterniond(q0 * turn) : Eigen::Quaterniond(turn * q0);
    // q and -q are the same orientation; a pose source may hand over either.
    if (flip_signs && k % 2 == 1) q.coeffs() = -q.coeffs();
    tracker.update(t, q, v0 + accel * (t - kStartTime));
    if (k == 0) continue;
    const HeadMotion m = tracker.motion();
    ASSERT_LT(maxAbs(m.angular_velocity - expected), kTrackerTol) << "step " << k;
    ASSERT_LT(maxAbs(m.acceleration - accel), kTrackerTol) << "step " << k;
    ASSERT_NEAR(m.time, t, kExactTol);
  }
}

TEST(HeadMotionTracker, RecoversConstantSpinAndAcceleration) {
  for (const Vec3& axis :
       {Vec3(Vec3::UnitZ()), Vec3(Vec3::UnitX()), Vec3(Vec3(1.0, -2.0, 0.5).normalized())})
    for (double rate : {kSpinRate, -kSpinRate})
      for (bool body : {false, true})
        for (bool flip : {false, true}) expectConstantSpinRecovered(axis, rate, body, flip);
}

TEST(HeadMotionTracker, NoRotationGivesZeroRate) {
  HeadMotionTracker tracker;
  const Eigen::Quaterniond q = arbitraryOrientation();
  tracker.update(kStartTime, q, Vec3::Zero());
  tracker.update(kStartTime + kDt, q, Vec3::Zero());
  EXPECT_LT(maxAbs(tracker.motion().angular_velocity), kTrackerTol);
  EXPECT_TRUE(tracker.motion().angular_velocity.allFinite());
  EXPECT_EQ(tracker.motion().acceleration, Vec3::Zero());
}

// --------------------------------------------------------------------------------------------
// Validation
// --------------------------------------------------------------------------------------------

void expectConfigError(const ImuOptions& o, const std::string& field) {
  SCOPED_TRACE(field);
  const std::string message = testing::errorMessageOf<ConfigError>([&] { o.validate(); });
  EXPECT_TRUE(contains(message, field)) << message;
  EXPECT_THROW(ImuModel(o, kGravity), ConfigError);
}

TEST(ImuOptions, RejectsUnusableValuesNamingTheField) {
  EXPECT_NO_THROW(ImuOptions{}.validate());
  EXPECT_NO_THROW(ImuModel(ImuOptions{}, kGravity));
  ImuOptions o;
  o.rate = 0.0;
  expectConfigError(o, "imu.rate");
  o.rate = -100.0;
  expectConfigError(o, "imu.rate");
  o.rate = kNaN;
  expectConfigError(o, "imu.rate");
  for (double bad : {-0.1, kNaN}) {
    SCOPED_TRACE(bad);
    o = ImuOptions{};
    o.orientation_noise_std = bad;
    expectConfigError(o, "imu.orientation_noise_std");
    o = ImuOptions{};
    o.gyro_noise_std = bad;
    expectConfigError(o, "imu.gyro_noise_std");
    o = ImuOptions{};
    o.accel_noise_std = bad;
    expectConfigError(o, "imu.accel_noise_std");
  }
  o = ImuOptions{};
  o.gyro_bias = Vec3(0.0, kNaN, 0.0);
  expectConfigError(o, "imu.gyro_bias");
  o = ImuOptions{};
  o.accel_bias = Vec3(0.0, 0.0, std::numeric_limits<double>::infinity());
  expectConfigError(o, "imu.accel_bias");
}

}  // namespace
}  // namespace flagella
