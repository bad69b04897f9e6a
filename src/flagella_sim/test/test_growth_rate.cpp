// The growth-rate threshold (docs/model.md 8.4.4) on signals and rate laws with closed forms: the
// slow part of a tilt that turns with the flagellum plus one fixed in space, the log-slope of an
// exponential with and without noise, and the zero of sigma(rate) from any guesses.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <random>

#include "flagella_sim/analysis/growth_rate.h"

namespace flagella {
namespace {

constexpr double kSigma = 0.013;     // [1/s]
constexpr double kPeriod = 15.0;     // [s], a turn at 4 rpm
constexpr double kLean = 0.05;       // the straight state's lean, turning with the flagellum
constexpr double kSlowStart = 0.02;  // the buckling mode's lean at t = 0, fixed in space

constexpr double kRemainder = 0.004;  // a constant lean that does not average out

// lean(t) = kLean (cos wt, sin wt, 0) + kRemainder (1, 0, 0)
//         + kSlowStart e^{sigma t} (cos phi(t), sin phi(t), 0), phi = 0.01 t (slow precession),
// sampled every `dt` over `duration`.
void makeSeries(double dt, double duration, std::vector<double>& t, std::vector<Vec3>& v) {
  const double w = 2.0 * M_PI / kPeriod;
  for (double s = 0.0; s <= duration + 1e-9; s += dt) {
    t.push_back(s);
    const double slow = kSlowStart * std::exp(kSigma * s), phi = 0.01 * s;
    v.emplace_back(kLean * std::cos(w * s) + kRemainder + slow * std::cos(phi),
                   kLean * std::sin(w * s) + slow * std::sin(phi), 0.0);
  }
}

TEST(GrowthRate, SlowAmplitudeRemovesTheTurningLeanAndTheRemainderAndKeepsTheGrowth) {
  std::vector<double> t;
  std::vector<Vec3> v;
  makeSeries(kPeriod / 24.0, 150.0, t, v);
  const AmplitudeSeries slow = slowTiltAmplitude(t, v, kPeriod);
  ASSERT_GT(slow.time.size(), 100u);
  EXPECT_NEAR(slow.time.front(), kPeriod, 1e-9);  // only whole two-turn windows inside
  EXPECT_LE(slow.time.back(), 150.0 - kPeriod + 1e-9);
  // the mean over a turn of c e^{z s}, z = sigma + 0.01 i: c e^{z t} F, F = sinh(z P/2)/(z P/2);
  // its change over a turn |c F 2 sinh(z P/2)| e^{sigma t}; the remainder stays in the mean only
  const std::complex<double> z(kSigma, 0.01), half = 0.5 * kPeriod * z;
  const std::complex<double> factor = std::sinh(half) / half;
  for (size_t k = 0; k < slow.time.size(); ++k) {
    const double tk = slow.time[k];
    const std::complex<double> mode = kSlowStart * std::exp(z * tk) * factor;
    EXPECT_NEAR(slow.amplitude[k], std::abs(mode + kRemainder), 2e-3 * std::abs(mode)) << tk;
    const double change =
        std::abs(kSlowStart * factor * 2.0 * std::sinh(half)) * std::exp(kSigma * tk);
    EXPECT_NEAR(slow.change[k], change, 2e-3 * change) << tk;
  }
  const LogSlopeFit fit = fitLogSlope(slow, 30.0, 130.0);
  ASSERT_TRUE(fit.ok) << fit.message;
  EXPECT_NEAR(fit.slope, kSigma, 1e-4);
}

TEST(GrowthRate, LogSlopeOfAnExponentialAndItsErrorUnderNoise) {
  AmplitudeSeries s;
  for (int k = 0; k <= 200; ++k) {
    s.time.push_back(0.5 * k);
    s.change.push_back(0.3 * std::exp(-0.021 * 0.5 * k));
  }
  LogSlopeFit fit = fitLogSlope(s, 10.0, 90.0);
  ASSERT_TRUE(fit.ok);
  EXPECT_NEAR(fit.slope, -0.021, 1e-12);
  EXPECT_LT(fit.error, 1e-12);
  EXPECT_NEAR(fit.t_from, 10.0, 1e-12);
  EXPECT_NEAR(fit.t_to, 90.0, 1e-12);
  EXPECT_EQ(fit.samples, 161);
  // 5 % multiplicative noise: over 40 seeds the slope lies within 3 errors of the truth
  int inside = 0;
  for (unsigned seed = 1; seed <= 40; ++seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> noise(0.0, 0.05);
    AmplitudeSeries n = s;
    for (double& a : n.change) a *= std::exp(noise(rng));
    fit = fitLogSlope(n, 0.0, 100.0);
    inside += std::abs(fit.slope + 0.021) < 3.0 * fit.error;
  }
  EXPECT_GE(inside, 38);
  EXPECT_FALSE(fitLogSlope(s, 50.0, 51.0).ok);  // 3 samples: no fit
}

AmplitudeSeries exponential(double a0, double sigma, double floor, double duration) {
  AmplitudeSeries s;
  for (double t = 5.0; t <= duration + 1e-9; t += 0.5) {
    s.time.push_back(t);
    s.amplitude.push_back(a0 * std::exp(sigma * (t - 5.0)) + floor);
    s.change.push_back(s.amplitude.back());  // the same signal drives both limits here
  }
  return s;
}

TEST(GrowthRate, ReadingStopsAtTheSmallTiltLimitAndAboveTheFloor) {
  const double limit = 0.17, quarter = 0.25;
  // growing: the window ends where the amplitude passes the limit
  GrowthReading r =
      readGrowth(exponential(0.02, 0.02, 0.0, 400.0), 40.0, 15.0, limit, quarter, 0.05);
  ASSERT_TRUE(r.message.empty()) << r.message;
  EXPECT_FALSE(r.grew_early || r.decayed_early);
  EXPECT_NEAR(r.sigma, 0.02, 1e-9);
  EXPECT_NEAR(r.to, 5.0 + std::log(limit / 0.02) / 0.02, 0.5);
  // decaying onto a floor: the window ends at a quarter of its start, before the floor bends it
  r = readGrowth(exponential(0.05, -0.03, 2e-4, 400.0), 20.0, 15.0, limit, quarter, 0.05);
  EXPECT_FALSE(r.decayed_early);
  EXPECT_NEAR(r.sigma, -0.03, 0.002);
  const double at_settle = 0.05 * std::exp(-0.03 * 15.0) + 2e-4;
  EXPECT_NEAR(r.to, 5.0 + std::log(0.05 / (quarter * at_settle - 2e-4)) / 0.03, 0.5);
  // fast growth past the limit before the window: a positive bound, no error
  r = readGrowth(exponential(0.02, 0.2, 0.0, 100.0), 40.0, 15.0, limit, quarter, 0.05);
  EXPECT_TRUE(r.grew_early);
  EXPECT_GT(r.sigma, 0.0);
  EXPECT_EQ(r.error, 0.0);
  // fast decay to a quarter within a turn of the window's start: a negative bound from there
  r = readGrowth(exponential(0.05, -0.12, 0.0, 100.0), 10.0, 15.0, limit, quarter, 0.05);
  EXPECT_TRUE(r.decayed_early);
  EXPECT_NEAR(r.from, 10.0, 1e-9);
  EXPECT_NEAR(r.sigma, -0.12, 1e-9);
  // a fall before the window (the spin-up's transient) does not decide the sign
  AmplitudeSeries dip = exponential(0.05, 0.01, 0.0, 200.0);
  for (size_t k = 0; k < dip.time.size(); ++k)
    dip.change[k] += 0.5 * std::exp(-0.2 * (dip.time[k] - 5.0));
  r = readGrowth(dip, 40.0, 15.0, limit, quarter, 0.05);
  EXPECT_FALSE(r.decayed_early || r.grew_early);
  EXPECT_GT(r.sigma, 0.0);
  // ... unless it falls below 5 % of its peak: then the window would read numerical remainders
  AmplitudeSeries gone = exponential(1e-4, 0.01, 0.0, 200.0);
  for (size_t k = 0; k < gone.time.size(); ++k)
    gone.change[k] += 0.5 * std::exp(-0.2 * (gone.time[k] - 5.0));
  r = readGrowth(gone, 40.0, 15.0, limit, quarter, 0.05);
  EXPECT_TRUE(r.decayed_early);
  EXPECT_NEAR(r.from, 5.0, 1e-9);
  EXPECT_LT(r.sigma, -0.1);
  EXPECT_FALSE(readGrowth(AmplitudeSeries{}, 40.0, 15.0, limit, quarter, 0.05).message.empty());
}

GrowthProbe linearSigma(double rate, double zero, double error) {
  GrowthProbe p;
  p.rate = rate;
  p.sigma = 0.01 * (rate - zero);
  p.sigma_error = error;
  return p;
}

TEST(GrowthRate, ThresholdIsTheZeroOfSigmaFromAnyGuesses) {
  for (double zero : {0.9, 3.6, 67.0, 300.0}) {
    for (auto [low, high] : {std::pair{2.0, 20.0}, std::pair{10.0, 100.0}, std::pair{1.0, 1.5}}) {
      GrowthThresholdOptions o;
      o.low = low;
      o.high = high;
      const GrowthThreshold g =
          findGrowthThreshold([&](double r) { return linearSigma(r, zero, 1e-4); }, o);
      ASSERT_TRUE(g.found) << zero << " " << g.message;
      EXPECT_NEAR(g.threshold, zero, 1e-9 * zero);  // a straight line: interpolation is exact
      EXPECT_LE(g.low, zero);
      EXPECT_GE(g.high, zero);
      // one-sigma error of the zero: sigma error over the slope, at most (both ends' errors)
      EXPECT_GT(g.uncertainty, 0.0);
      EXPECT_LE(g.uncertainty, 1e-4 / 0.01 + 1e-12);
      EXPECT_LE(static_cast<int>(g.runs.size()), o.max_runs);
    }
  }
}

TEST(GrowthRate, CurvedSigmaConvergesWithinTheTolerance) {
  GrowthThresholdOptions o;
  o.tolerance = 0.01;
  auto curved = [](double r) {
    GrowthProbe p;
    p.sigma = 0.002 * (r * r - 16.0);  // zero at 4 rpm
    p.sigma_error = 1e-4;
    return p;
  };
  const GrowthThreshold g = findGrowthThreshold(curved, o);
  ASSERT_TRUE(g.found) << g.message;
  EXPECT_NEAR(g.threshold, 4.0, 0.01 * 4.0);
}

TEST(GrowthRate, FailedRunsAndMissingBracketsAreReported) {
  GrowthThresholdOptions o;
  o.low = 2.0;
  o.high = 20.0;
  int calls = 0;
  GrowthThreshold g = findGrowthThreshold(
      [&](double r) {
        GrowthProbe p = linearSigma(r, 5.0, 1e-4);
        p.failed = ++calls == 2;
        p.error = "Newton diverged";
        return p;
      },
      o);
  EXPECT_FALSE(g.found);
  EXPECT_NE(g.message.find("Newton diverged"), std::string::npos) << g.message;
  EXPECT_EQ(g.runs.size(), 2u);
  o.min_rate = 1.0;
  g = findGrowthThreshold([&](double r) { return linearSigma(r, 0.1, 1e-4); }, o);
  EXPECT_FALSE(g.found);
  EXPECT_NE(g.message.find("lowest rate"), std::string::npos) << g.message;
  o.max_rate = 100.0;
  g = findGrowthThreshold([&](double r) { return linearSigma(r, 500.0, 1e-4); }, o);
  EXPECT_FALSE(g.found);
  EXPECT_NE(g.message.find("highest rate"), std::string::npos) << g.message;
  o.tolerance = 0.7;
  EXPECT_THROW(validate(o), std::invalid_argument);
}

}  // namespace
}  // namespace flagella
