// NeutralTrim (neutral_trim.h) against the closed form of the pitch under a constant couple
// (docs/model.md 7.4): de/dt = k cos(e) (x - x_n) gives e(t) = gd(gd^-1(e_0) + k (x - x_n) t),
// gd the Gudermann function, gd(u) = 2 atan(tanh(u / 2)).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "flagella_control/neutral_trim.h"

using flagella::control::NeutralTrim;

namespace {

double gd(double u) { return 2.0 * std::atan(std::tanh(0.5 * u)); }
double gdInverse(double e) { return std::atanh(std::sin(e)); }

constexpr double kPitchRate = 150.0;  // [rad/s per slider metre]
constexpr double kNeutral = -1.2e-3;  // [m]
constexpr double kDt = 0.01;          // [s]

// Feeds 30 s of samples: the slider at `first` for 12 s, then at `second` (each segment from the
// closed form), plus `wobble` [rad] at the period of the flagellum and white `noise` [rad].
NeutralTrim feed(double first, double second, double wobble, double noise, unsigned seed) {
  NeutralTrim trim;
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, noise);
  double e0 = 0.05, t0 = 0.0, held = first;
  for (int k = 0; k <= 3000; ++k) {
    const double t = k * kDt;
    if (t > 12.0 && held == first) {  // switch: the new segment starts where the last one is
      e0 = gd(gdInverse(e0) + kPitchRate * (held - kNeutral) * (12.0 - t0));
      t0 = 12.0;
      held = second;
    }
    const double e = gd(gdInverse(e0) + kPitchRate * (held - kNeutral) * (t - t0));
    const double measured =
        e + wobble * std::sin(2.0 * M_PI * t / 7.6) + (noise > 0 ? gauss(rng) : 0.0);
    // The slider held over the interval ending now: `first` up to 12 s.
    trim.add(k == 0 ? 0.0 : kDt, measured, t <= 12.0 + 1e-12 ? first : second, kPitchRate);
  }
  return trim;
}

}  // namespace

TEST(NeutralTrim, FindsTheNeutralFromTheClosedFormPitch) {
  // 200 um off the neutral, then 100 um the other way: pitching up, then down.
  const NeutralTrim trim = feed(kNeutral + 2e-4, kNeutral - 1e-4, 0.0, 0.0, 1);
  EXPECT_EQ(trim.samples(), 3001);
  // First-order integration of S and C over 10 ms steps: within 1 % of the offsets.
  EXPECT_NEAR(trim.neutral(), kNeutral, 2e-6);
  EXPECT_LT(trim.standardError(), 1e-6);
}

TEST(NeutralTrim, AHeadHeldAtTheNeutralGivesItToo) {
  // Held at the neutral the elevation stays put: the line is flat and the neutral is where the
  // slider is.
  const NeutralTrim level = feed(kNeutral, kNeutral, 0.0, 0.0, 1);
  EXPECT_NEAR(level.neutral(), kNeutral, 1e-9);
  // Before three samples there is no estimate.
  NeutralTrim empty;
  empty.add(0.0, 0.0, 0.0, kPitchRate);
  EXPECT_TRUE(std::isnan(empty.neutral()));
  EXPECT_TRUE(std::isnan(empty.standardError()));
}

TEST(NeutralTrim, WobbleAndNoiseWidenTheEstimateAsItsErrorSays) {
  // 1 deg of wobble at the flagellum's period and 0.5 deg of white noise: over seeds the
  // estimate scatters about the truth by about its standard error (white-noise model; the
  // wobble is correlated, so allow 4 standard errors and a 10 um bound).
  for (unsigned seed = 1; seed <= 10; ++seed) {
    const NeutralTrim trim =
        feed(kNeutral + 2e-4, kNeutral + 2e-4, 1.0 * M_PI / 180, 0.5 * M_PI / 180, seed);
    EXPECT_NEAR(trim.neutral(), kNeutral, std::max(4.0 * trim.standardError(), 1e-5))
        << "seed " << seed;
  }
}
