// Tests of the simulated overhead camera: a noise-free fix is the snapshot's head centre x, y in
// the output frame (also for a config whose `up` is not z), noise has the configured mean and
// standard deviation (sample statistics), the seed fixes the sequence, the dropout window and
// rate 0 withhold fixes, and unusable options are refused naming the field.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "flagella_sim/core/parameter_set.h"
#include "flagella_sim/runtime/camera_model.h"
#include "flagella_sim/runtime/rate_schedule.h"
#include "flagella_sim/runtime/sim_session.h"
#include "flagella_sim/simulation/simulation_config.h"
#include "support/temp_dir.h"

namespace flagella {
namespace {

constexpr char kConfigDir[] = FLAGELLA_CONFIG_DIR;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Copies of the same doubles: nothing but round-off of one rotation.
constexpr double kExactTol = 1e-15;
constexpr int kSomeSteps = 30;
constexpr int kMovingSteps = 100;   // 1 s: the interface robot's head has moved by millimetres
constexpr double kMovedTol = 1e-5;  // [m]

constexpr int kSamples = 20000;
constexpr double kNoiseStd = 0.004;  // [m]
// Sample std of N normal draws has relative standard error 1/sqrt(2N) = 0.5%: 3% is 6 of those.
constexpr double kStdRelTol = 0.03;
// The sample mean has standard error sigma/sqrt(N): 4 of those.
constexpr double kMeanSigmas = 4.0;
// The sample correlation of independent axes has standard error 1/sqrt(N) = 0.7%: 4 of those.
constexpr double kCorrelationTol = 4.0 / 141.42;

const Vec3 kTruth(0.31, -0.27, 0.05);  // [m], output frame

SimulationConfig load(const std::string& name) {
  return loadSimulationConfig(std::string(kConfigDir) + "/" + name, {});
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

void expectConfigError(const CameraOptions& o, const std::string& field) {
  SCOPED_TRACE(field);
  const std::string message = testing::errorMessageOf<ConfigError>([&] { o.validate(); });
  EXPECT_TRUE(contains(message, field)) << message;
}

// --------------------------------------------------------------------------------------------
// Noise-free fixes: the snapshot's head centre
// --------------------------------------------------------------------------------------------

TEST(CameraModel, NoiseFreeFixIsTheHorizontalPartOfTheTruth) {
  CameraModel camera(CameraOptions{});
  const CameraFix fix = camera.measure(1.25, kTruth);
  EXPECT_EQ(fix.time, 1.25);
  EXPECT_EQ(fix.position.x(), kTruth.x());
  EXPECT_EQ(fix.position.y(), kTruth.y());
  EXPECT_EQ(fix.variance, 0.0);
}

TEST(CameraModel, StereoFixAddsTheHeightWithItsOwnNoise) {
  CameraModel overhead(CameraOptions{});
  EXPECT_FALSE(overhead.measure(0.0, kTruth).has_height);
  EXPECT_EQ(overhead.measure(0.0, kTruth).height, 0.0);
  CameraOptions o;
  o.stereo = true;
  CameraModel exact(o);
  const CameraFix fix = exact.measure(0.0, kTruth);
  EXPECT_TRUE(fix.has_height);
  EXPECT_EQ(fix.height, kTruth.z());
  o.height_noise_std = 2e-3;
  CameraModel noisy(o);
  double sum = 0.0, sum2 = 0.0;
  const int n = 4000;
  for (int i = 0; i < n; ++i) {
    const double e = noisy.measure(0.0, kTruth).height - kTruth.z();
    sum += e, sum2 += e * e;
  }
  // mean within 4 standard errors, std within 5 % (n = 4000: its relative error is 1.1 %)
  EXPECT_NEAR(sum / n, 0.0, 4 * 2e-3 / std::sqrt(n));
  EXPECT_NEAR(std::sqrt(sum2 / n), 2e-3, 0.05 * 2e-3);
  o.height_noise_std = -1.0;
  EXPECT_THROW(CameraModel{o}, ConfigError);
}

TEST(CameraModel, SessionFixIsTheSnapshotHeadPositionInTheOutputFrame) {
  // Design 1 has z up already; the interface robot's `up` is +y, so the output frame rotation
  // matters: the fix must be the snapshot's (rotated) head x, y, not the simulation's.
  for (const char* name : {"granular_design1.yaml", "interface_robot.yaml"}) {
    SCOPED_TRACE(name);
    SimSession session(load(name), SessionOptions{});
    for (int k = 0; k < kSomeSteps; ++k) ASSERT_TRUE(session.step());
    const RodSnapshot snap = session.snapshot();
    const CameraFix fix = session.measureCamera();
    EXPECT_EQ(fix.time, session.time());
    EXPECT_NEAR(fix.position.x(), snap.head_position.x(), kExactTol);
    EXPECT_NEAR(fix.position.y(), snap.head_position.y(), kExactTol);
    EXPECT_EQ(fix.variance, 0.0);
    EXPECT_TRUE(session.cameraAvailable());
  }
  // The interface robot's simulation frame (y up, head axis along z) differs from the output
  // frame: once the head has moved along its axis, the simulation's x, y are not the fix.
  SimSession session(load("interface_robot.yaml"), SessionOptions{});
  for (int k = 0; k < kMovingSteps; ++k) ASSERT_TRUE(session.step());
  const Vec3 sim_position = session.simulation().sample().head_position;
  const CameraFix fix = session.measureCamera();
  EXPECT_GT((sim_position.head<2>() - fix.position).norm(), kMovedTol) << sim_position.transpose();
  const Vec3 output_position = session.outputFrame() * sim_position;
  EXPECT_LT((output_position.head<2>() - fix.position).cwiseAbs().maxCoeff(), kExactTol);
}

// --------------------------------------------------------------------------------------------
// Noise statistics and seeding
// --------------------------------------------------------------------------------------------

TEST(CameraModel, NoiseHasTheConfiguredMeanAndStandardDeviation) {
  CameraOptions o;
  o.noise_std = kNoiseStd;
  CameraModel camera(o);
  std::vector<Eigen::Vector2d> errors;
  errors.reserve(kSamples);
  for (int i = 0; i < kSamples; ++i) {
    const CameraFix fix = camera.measure(0.0, kTruth);
    ASSERT_EQ(fix.variance, kNoiseStd * kNoiseStd);
    errors.push_back(fix.position - kTruth.head<2>());
  }
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& e : errors) mean += e;
  mean /= kSamples;
  Eigen::Vector2d var = Eigen::Vector2d::Zero();
  double covariance = 0.0;
  for (const auto& e : errors) {
    var += (e - mean).cwiseAbs2();
    covariance += (e.x() - mean.x()) * (e.y() - mean.y());
  }
  var /= kSamples - 1;
  covariance /= kSamples - 1;
  const double mean_tol = kMeanSigmas * kNoiseStd / std::sqrt(static_cast<double>(kSamples));
  for (int axis = 0; axis < 2; ++axis) {
    EXPECT_NEAR(mean[axis], 0.0, mean_tol) << "axis " << axis;
    EXPECT_NEAR(std::sqrt(var[axis]), kNoiseStd, kStdRelTol * kNoiseStd) << "axis " << axis;
  }
  EXPECT_LT(std::abs(covariance / std::sqrt(var.x() * var.y())), kCorrelationTol);
}

TEST(CameraModel, SameSeedSameSequenceOtherSeedOtherSequence) {
  CameraOptions o;
  o.noise_std = kNoiseStd;
  CameraModel a(o), b(o);
  o.seed += 1;
  CameraModel c(o);
  int differing = 0;
  for (int i = 0; i < 100; ++i) {
    const CameraFix fa = a.measure(0.01 * i, kTruth);
    const CameraFix fb = b.measure(0.01 * i, kTruth);
    const CameraFix fc = c.measure(0.01 * i, kTruth);
    ASSERT_EQ(fa.position, fb.position) << "fix " << i;
    differing += fa.position != fc.position;
  }
  EXPECT_EQ(differing, 100);
}

// --------------------------------------------------------------------------------------------
// Availability: rate 0 and the dropout window
// --------------------------------------------------------------------------------------------

TEST(CameraModel, DropoutWindowWithholdsFixes) {
  CameraOptions o;
  o.dropout_start = 1.0;
  o.dropout_end = 2.0;
  CameraModel camera(o);
  EXPECT_TRUE(camera.available(0.0));
  EXPECT_TRUE(camera.available(0.999));
  EXPECT_FALSE(camera.available(1.0));
  EXPECT_FALSE(camera.available(1.0 - 1e-12));  // a summed-up 1.0 is 1.0
  EXPECT_FALSE(camera.available(1.5));
  EXPECT_FALSE(camera.available(1.999));
  EXPECT_TRUE(camera.available(2.0 - 1e-12));  // the window ends at 2.0
  EXPECT_TRUE(camera.available(2.0));
  EXPECT_TRUE(camera.available(100.0));
  // No window by default.
  EXPECT_TRUE(CameraModel(CameraOptions{}).available(1.5));
}

TEST(CameraModel, RateZeroIsOff) {
  CameraOptions o;
  o.rate = 0.0;
  EXPECT_NO_THROW(o.validate());
  EXPECT_FALSE(CameraModel(o).available(0.0));
  EXPECT_FALSE(CameraModel(o).available(10.0));
}

TEST(CameraModel, SessionPublishingLoopSkipsTheDropoutWindow) {
  // What the node and the LCM harness do: a 2 Hz schedule on the session's clock, fixes only
  // while available. Window [0.5, 1.5): the fixes due at 0.5 and 1.0 are withheld.
  SessionOptions options;
  options.camera.dropout_start = 0.5;
  options.camera.dropout_end = 1.5;
  SimSession session(load("granular_design1.yaml"), options);
  RateSchedule schedule(options.camera.rate);
  std::vector<double> fixes;
  if (schedule.due(session.time()) && session.cameraAvailable())
    fixes.push_back(session.measureCamera().time);
  while (session.time() < 2.5 - 0.5 * session.dt()) {
    ASSERT_TRUE(session.step());
    if (schedule.due(session.time()) && session.cameraAvailable())
      fixes.push_back(session.measureCamera().time);
  }
  const std::vector<double> expected = {0.0, 1.5, 2.0, 2.5};
  ASSERT_EQ(fixes.size(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i) EXPECT_NEAR(fixes[i], expected[i], 1e-9);
}

// --------------------------------------------------------------------------------------------
// Option validation
// --------------------------------------------------------------------------------------------

TEST(CameraOptions, RejectsUnusableValuesNamingTheField) {
  EXPECT_NO_THROW(CameraOptions{}.validate());
  for (double bad : {-1.0, kNaN, 1e6}) {
    CameraOptions o;
    o.rate = bad;
    expectConfigError(o, "camera.rate");
  }
  for (double bad : {-0.1, kNaN, std::numeric_limits<double>::infinity()}) {
    CameraOptions o;
    o.noise_std = bad;
    expectConfigError(o, "camera.noise_std");
  }
  CameraOptions o;
  o.dropout_start = kNaN;
  expectConfigError(o, "camera.dropout_start");
  o = CameraOptions{};
  o.dropout_start = 2.0;
  o.dropout_end = 1.0;  // ends before it starts
  expectConfigError(o, "camera.dropout_end");
  o.dropout_end = kNaN;
  expectConfigError(o, "camera.dropout_end");
  o = CameraOptions{};
  o.dropout_end = 3.0;  // an end without a start
  expectConfigError(o, "camera.dropout_end");
  // The range is in the message.
  o = CameraOptions{};
  o.rate = -1.0;
  EXPECT_TRUE(contains(testing::errorMessageOf<ConfigError>([&] { o.validate(); }), "[0, "));
  // SessionOptions validates its camera, and the session refuses bad options.
  SessionOptions session_options;
  session_options.camera.noise_std = -1.0;
  EXPECT_TRUE(contains(testing::errorMessageOf<ConfigError>([&] { session_options.validate(); }),
                       "camera.noise_std"));
  EXPECT_THROW(SimSession(load("granular_design1.yaml"), session_options), ConfigError);
  EXPECT_THROW(CameraModel{o}, ConfigError);
}

}  // namespace
}  // namespace flagella
