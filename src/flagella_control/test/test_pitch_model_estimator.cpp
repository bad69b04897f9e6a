// PitchModelEstimator (pitch_model_estimator.h) against the closed form of the pitch under a
// piecewise constant couple (docs/model.md 7.4): de/dt = a cos(e) (x - x_n) gives
// gd^-1(e) growing by a (x - x_n) t over each interval, gd(u) = 2 atan(tanh(u / 2)).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "flagella_control/neutral_trim.h"
#include "flagella_control/pitch_model_estimator.h"

using flagella::control::NeutralTrim;
using flagella::control::PitchModelEstimator;

namespace {

double gd(double u) { return 2.0 * std::atan(std::tanh(0.5 * u)); }
double gdInverse(double e) { return std::atanh(std::sin(e)); }

constexpr double kCalibratedRate = 150.0;  // k [rad/s per slider metre]
constexpr double kPark = -1.0e-3;          // reference x_r [m]
constexpr double kDt = 0.01;               // [s]

struct Truth {
  double rate_factor = 0.8;       // a / k: the model's pitch rate 25 % too high
  double neutral = kPark - 2e-4;  // x_n [m]
};

// The slider a mission would command: near `cruise` with +-40 um of steering, and a pitching
// offset of +-300 um for 5 s every 40 s (alternating). Held over [t, t + dt).
double slider(double t, double cruise) {
  const double steering = 4e-5 * std::sin(2.0 * M_PI * t / 90.0);
  const double phase = std::fmod(t, 40.0);
  if (phase >= 20.0 && phase < 25.0)
    return cruise + (static_cast<int>(t / 40.0) % 2 == 0 ? 3e-4 : -3e-4);
  return cruise + steering;
}

// Feeds `seconds` of exact pitch, with `wobble` [rad] at the flagellum's period (7.6 s) and white
// `noise` [rad], to the estimator and (alpha fixed at 1) to a NeutralTrim.
void feed(const Truth& truth, double cruise, double seconds, double wobble, double noise,
          unsigned seed, PitchModelEstimator& estimator, NeutralTrim* trim = nullptr) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, noise);
  double psi = gdInverse(0.02);  // gd^-1 of the elevation
  double held = slider(0.0, cruise);
  const long steps = std::lround(seconds / kDt);
  for (long k = 0; k <= steps; ++k) {
    const double t = k * kDt;
    if (k > 0) psi += truth.rate_factor * kCalibratedRate * (held - truth.neutral) * kDt;
    const double e = gd(psi);
    const double measured =
        e + wobble * std::sin(2.0 * M_PI * t / 7.6) + (noise > 0.0 ? gauss(rng) : 0.0);
    estimator.add(k == 0 ? 0.0 : kDt, measured, held);
    if (trim) trim->add(k == 0 ? 0.0 : kDt, measured, held, kCalibratedRate);
    held = slider(t, cruise);
  }
}

}  // namespace

TEST(PitchModelEstimator, FindsTheNeutralAndThePitchRateTheModelGetsWrong) {
  // The neutral 200 um from the park position, the pitch rate 20 % below the calibrated one;
  // the robot cruising 30 um off the neutral (the start frame's trim left that much): both are
  // found, where the one-parameter trim (rate fixed at the calibrated one) is biased.
  const Truth truth;
  PitchModelEstimator estimator(kCalibratedRate, kPark, 1e9);
  NeutralTrim trim;
  feed(truth, truth.neutral + 3e-5, 200.0, 0.0, 0.0, 1, estimator, &trim);
  double alpha = NAN, neutral = NAN;
  ASSERT_TRUE(estimator.estimate(alpha, neutral));
  // Exact data: the prior on alpha and the first-order integration over 10 ms steps leave a
  // fraction of a per cent.
  EXPECT_NEAR(alpha, truth.rate_factor, 0.01);
  EXPECT_NEAR(neutral, truth.neutral, 1e-6);
  double standard_error = NAN;
  ASSERT_TRUE(estimator.estimate(alpha, neutral, standard_error));
  EXPECT_LT(standard_error, 1e-6) << "exact data scatter little about the fit";
  EXPECT_GT(std::abs(trim.neutral() - truth.neutral), 5e-6) << "the fixed-rate trim is biased";
  EXPECT_NEAR(estimator.seconds(), 200.0, 1e-6);
}

TEST(PitchModelEstimator, WithoutPitchingThePriorHoldsTheRateAndTheNeutralStillFollows) {
  // Held at one slider position the rate cannot be told from the offset: alpha stays at the
  // prior (1) and the neutral carries the whole pitch, k (x - x_n) matching a (x - x_n,true).
  const Truth truth;
  PitchModelEstimator estimator(kCalibratedRate, kPark, 1e9);
  const double held = truth.neutral + 3e-5;
  std::mt19937 rng(1);
  double psi = 0.0;
  for (long k = 0; k <= 6000; ++k) {
    if (k > 0) psi += truth.rate_factor * kCalibratedRate * (held - truth.neutral) * kDt;
    estimator.add(k == 0 ? 0.0 : kDt, gd(psi), held);
  }
  double alpha = NAN, neutral = NAN;
  ASSERT_TRUE(estimator.estimate(alpha, neutral));
  EXPECT_NEAR(alpha, 1.0, 1e-6);
  EXPECT_NEAR(kCalibratedRate * alpha * (held - neutral),
              truth.rate_factor * kCalibratedRate * (held - truth.neutral), 1e-7);
}

TEST(PitchModelEstimator, ForgetsAnOldNeutral) {
  // 300 s with the neutral at one place, then 300 s with it 100 um away: with a 60 s forgetting
  // time the estimate is the new one.
  Truth before;
  Truth after = before;
  after.neutral = before.neutral + 1e-4;
  PitchModelEstimator estimator(kCalibratedRate, kPark, 60.0);
  feed(before, before.neutral + 3e-5, 300.0, 0.0, 0.0, 1, estimator);
  double alpha = NAN, neutral = NAN;
  ASSERT_TRUE(estimator.estimate(alpha, neutral));
  EXPECT_NEAR(neutral, before.neutral, 5e-6);  // the prior on alpha over a 60 s window
  // The integrals continue: feed the second half from where the first one ends.
  feed(after, after.neutral + 3e-5, 300.0, 0.0, 0.0, 1, estimator);
  ASSERT_TRUE(estimator.estimate(alpha, neutral));
  EXPECT_NEAR(neutral, after.neutral, 5e-6);
}

TEST(PitchModelEstimator, WobbleAndNoiseLeaveTheNeutralWithinMicrometres) {
  // 3 deg of wobble at the flagellum's period and 0.5 deg of white noise, over 10 seeds.
  const Truth truth;
  for (unsigned seed = 1; seed <= 10; ++seed) {
    PitchModelEstimator estimator(kCalibratedRate, kPark, 120.0);
    feed(truth, truth.neutral + 3e-5, 300.0, 3.0 * M_PI / 180, 0.5 * M_PI / 180, seed, estimator);
    double alpha = NAN, neutral = NAN, standard_error = NAN;
    ASSERT_TRUE(estimator.estimate(alpha, neutral, standard_error));
    EXPECT_NEAR(neutral, truth.neutral, 5e-6) << "seed " << seed;
    EXPECT_NEAR(alpha, truth.rate_factor, 0.1) << "seed " << seed;
    // Its standard error covers the error (within 4; the wobble is not white) and is of the
    // size of the 5 um bound.
    EXPECT_LE(std::abs(neutral - truth.neutral), 4.0 * standard_error) << "seed " << seed;
    EXPECT_LT(standard_error, 5e-6) << "seed " << seed;
  }
}

TEST(PitchModelEstimator, NoDataGivesNoEstimate) {
  PitchModelEstimator estimator(kCalibratedRate, kPark, 120.0);
  double alpha = NAN, neutral = NAN;
  EXPECT_FALSE(estimator.estimate(alpha, neutral));
  estimator.add(0.0, 0.1, kPark);
  EXPECT_FALSE(estimator.estimate(alpha, neutral));
  EXPECT_EQ(estimator.seconds(), 0.0);
}
