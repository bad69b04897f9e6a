// The bracketing + bisection search for a switching rate (docs/model.md 8.4.4) on properties with
// a known switch point: the result must bracket it within the tolerance, whatever the guesses.
// The smoothed crossing on the fixed rate grid (8.4.5) on indicators with a closed-form crossing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "flagella_sim/analysis/threshold_search.h"

namespace flagella {
namespace {

std::function<ThresholdProbe(double)> stepAt(double switch_rate, int* calls = nullptr) {
  return [=](double rate) {
    if (calls) ++*calls;
    ThresholdProbe p;
    p.above = rate > switch_rate;
    p.indicator = rate > switch_rate ? 40.0 : 2.0;
    return p;
  };
}

TEST(ThresholdSearch, BracketsTheSwitchFromAnyGuesses) {
  for (double truth : {0.7, 13.0, 37.3, 99.9, 640.0}) {
    for (auto [low, high] : {std::pair{10.0, 100.0}, std::pair{1.0, 2.0}, std::pair{50.0, 60.0}}) {
      ThresholdSearchOptions o;
      o.low = low;
      o.high = high;
      o.tolerance = 0.5;
      const ThresholdResult r = findThreshold(stepAt(truth), o);
      ASSERT_TRUE(r.found) << truth << " " << r.message;
      EXPECT_LE(r.low, truth);
      EXPECT_GT(r.high, truth);
      EXPECT_LE(r.high - r.low, o.tolerance);
      EXPECT_NEAR(r.threshold, truth, 0.5 * o.tolerance);
      for (const ThresholdProbe& p : r.runs) EXPECT_EQ(p.above, p.rate > truth);
    }
  }
}

TEST(ThresholdSearch, BisectionNeedsLogarithmicallyManyRuns) {
  int calls = 0;
  ThresholdSearchOptions o;  // 10 and 100 rpm bracket 37.3 at once
  o.tolerance = 90.0 / 1024.0;
  const ThresholdResult r = findThreshold(stepAt(37.3, &calls), o);
  ASSERT_TRUE(r.found);
  EXPECT_EQ(calls, 2 + 10);
  EXPECT_EQ(static_cast<int>(r.runs.size()), calls);
}

TEST(ThresholdSearch, ReportsWhyNoThresholdWasFound) {
  ThresholdSearchOptions o;
  o.max_rate = 500.0;
  ThresholdResult never = findThreshold(stepAt(1e9), o);
  EXPECT_FALSE(never.found);
  EXPECT_NE(never.message.find("below the threshold up to"), std::string::npos) << never.message;
  ThresholdResult always = findThreshold(stepAt(-1.0), o);
  EXPECT_FALSE(always.found);
  EXPECT_NE(always.message.find("above the threshold even at"), std::string::npos);
  const auto failing = [](double rate) {
    ThresholdProbe p;
    p.failed = rate > 50.0;
    p.error = "Newton did not converge";
    return p;
  };
  ThresholdResult failed = findThreshold(failing, o);
  EXPECT_FALSE(failed.found);
  EXPECT_NE(failed.message.find("100 rpm failed: Newton did not converge"), std::string::npos)
      << failed.message;
  o.max_runs = 3;
  EXPECT_FALSE(findThreshold(stepAt(37.3), o).found);
}

/// A probe whose indicator is `indicator(rate)`.
std::function<ThresholdProbe(double)> probeOf(const std::function<double(double)>& indicator) {
  return [=](double rate) {
    ThresholdProbe p;
    p.rate = rate;
    p.indicator = indicator(rate);
    return p;
  };
}

// A tilt linear in log rate: the three-rate average on a geometric grid is exact and so is the
// interpolation in log rate; the crossing is where 15 + 40 log(rate / 5.1) = 15.
double logLine(double rate) { return 15.0 + 40.0 * std::log(rate / 5.1); }

TEST(ThresholdSearch, SmoothedCrossingOfALogLineIsExact) {
  const WindowThreshold w = windowThreshold(probeOf(logLine), 5.0, 1.02, 4, 15.0);
  ASSERT_EQ(w.runs.size(), 9u);
  for (size_t i = 0; i < w.runs.size(); ++i)  // the global grid 1.02^k rpm
    EXPECT_NEAR(std::log(w.runs[i].rate) / std::log(1.02),
                std::round(std::log(w.runs[i].rate) / std::log(1.02)), 1e-9);
  EXPECT_NEAR(w.threshold, 5.1, 1e-12) << w.message;
}

// The largest tilt wobbles with the rate (alternating from one grid rate to the next): the
// crossing of neighbouring runs moves by wobble / slope, the averaged crossing much less; and it
// does not depend on where the window sits.
double wobbly(double rate) {
  const long k = std::lround(std::log(rate) / std::log(1.02));
  return logLine(rate) + (k % 2 == 0 ? 0.7 : -0.7);
}

TEST(ThresholdSearch, SmoothedCrossingAveragesAWobbleWhereverTheWindowSits) {
  const double slope_per_grid_step = 40.0 * std::log(1.02);  // deg per grid rate
  const double unsmoothed_shift = 5.1 * (std::pow(1.02, 0.7 / slope_per_grid_step) - 1.0);
  const double centred = windowThreshold(probeOf(wobbly), 5.1, 1.02, 4, 15.0).threshold;
  EXPECT_LT(std::abs(centred - 5.1), 0.5 * unsmoothed_shift) << centred;
  for (double center : {4.85, 4.95, 5.2, 5.3}) {  // two grid rates either way
    const WindowThreshold w = windowThreshold(probeOf(wobbly), center, 1.02, 4, 15.0);
    EXPECT_DOUBLE_EQ(w.threshold, centred) << center << " " << w.message;
  }
}

TEST(ThresholdSearch, SmoothedCrossingMovesContinuouslyWithTheIndicator) {
  // Raising every tilt by d moves the crossing down by about d / slope, in proportion while the
  // crossing stays between the same two rates.
  auto crossingRaisedBy = [](double d) {
    return windowThreshold(probeOf([d](double r) { return wobbly(r) + d; }), 5.1, 1.02, 4, 15.0)
        .threshold;
  };
  const double base = crossingRaisedBy(0.0);
  const double per_hundredth = crossingRaisedBy(0.01) - base;
  EXPECT_LT(per_hundredth, 0.0);
  EXPECT_NEAR(per_hundredth, -0.01 * 5.1 / 40.0, 0.5 * 0.01 * 5.1 / 40.0);
  for (double d : {0.002, 0.005, 0.02}) {
    const double moved = crossingRaisedBy(d) - base;
    EXPECT_NEAR(moved / per_hundredth, d / 0.01, 0.01 * d / 0.01) << d;
  }
}

TEST(ThresholdSearch, AWindowAwayFromTheCrossingMovesToItAndGivesTheSameThreshold) {
  const double centred = windowThreshold(probeOf(wobbly), 5.1, 1.02, 4, 15.0).threshold;
  for (double center : {3.0, 4.0, 6.5, 9.0}) {
    const WindowThreshold w = windowThreshold(probeOf(wobbly), center, 1.02, 4, 15.0);
    EXPECT_DOUBLE_EQ(w.threshold, centred) << center << " " << w.message;
    std::vector<double> rates;  // no rate run twice
    for (const ThresholdProbe& p : w.runs) rates.push_back(p.rate);
    std::sort(rates.begin(), rates.end());
    EXPECT_EQ(std::adjacent_find(rates.begin(), rates.end()), rates.end()) << center;
  }
}

TEST(ThresholdSearch, SmoothedCrossingIsNaNWhenItIsNotInside) {
  EXPECT_TRUE(std::isnan(windowThreshold(probeOf(logLine), 4.0, 1.02, 4, 15.0, 0).threshold));
  const WindowThreshold above = windowThreshold(probeOf(logLine), 6.5, 1.02, 4, 15.0, 1);
  EXPECT_TRUE(std::isnan(above.threshold));  // already above the criterion: crossing below
  EXPECT_NE(above.message.find("does not cross 15"), std::string::npos) << above.message;
  EXPECT_EQ(above.runs.size(), 9u + 6u);  // one move of 2 x 4 - 2 rates
  auto failing = [](double rate) {
    ThresholdProbe p;
    p.failed = rate > 5.2;
    p.error = "Newton did not converge";
    return p;
  };
  const WindowThreshold failed = windowThreshold(failing, 5.1, 1.02, 4, 15.0);
  EXPECT_TRUE(std::isnan(failed.threshold));
  EXPECT_NE(failed.message.find("failed: Newton did not converge"), std::string::npos);
  EXPECT_LT(failed.runs.size(), 9u);  // stopped at the failure
  std::vector<ThresholdProbe> two(2);
  EXPECT_TRUE(std::isnan(smoothedCrossing(two, 15.0)));
  EXPECT_THROW(windowThreshold(probeOf(logLine), 0.0, 1.02, 4, 15.0), std::invalid_argument);
  EXPECT_THROW(windowThreshold(probeOf(logLine), 5.0, 1.0, 4, 15.0), std::invalid_argument);
  EXPECT_THROW(windowThreshold(probeOf(logLine), 5.0, 1.02, 1, 15.0), std::invalid_argument);
}

TEST(ThresholdSearch, BadOptionsNameTheField) {
  ThresholdSearchOptions o;
  o.high = 5.0;
  try {
    findThreshold(stepAt(1.0), o);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("high = 5 must be > low (10)"), std::string::npos)
        << e.what();
  }
  o = {};
  o.tolerance = 0.0;
  EXPECT_THROW(findThreshold(stepAt(1.0), o), std::invalid_argument);
  o = {};
  o.low = std::nan("");
  EXPECT_THROW(findThreshold(stepAt(1.0), o), std::invalid_argument);
}

}  // namespace
}  // namespace flagella
