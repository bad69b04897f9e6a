// The derivative-free one-parameter search of the threshold fits (docs/model.md 8.4.5) on costs
// with a known minimum: smooth, at a bound, a staircase (what a threshold on a rate grid gives),
// and with points that cannot be evaluated.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>
#include <vector>

#include "../src/minimise_one_dimension.h"

namespace flagella {
namespace identify {
namespace {

/// Evaluates `f` at every point, counting the calls and the points.
struct Counted {
  explicit Counted(std::function<double(double)> cost) : f(std::move(cost)) {}
  std::function<double(double)> f;
  int calls = 0;
  std::vector<size_t> batch_sizes;
  std::vector<double> operator()(const std::vector<double>& xs) {
    ++calls;
    batch_sizes.push_back(xs.size());
    std::vector<double> out;
    for (double x : xs) out.push_back(f(x));
    return out;
  }
};

OneDimensionResult minimise(Counted& counted, double x0, OneDimensionOptions o) {
  return minimiseOneDimension([&](const std::vector<double>& xs) { return counted(xs); }, x0,
                              counted.f(x0), o);
}

OneDimensionOptions interval(double lower, double upper) {
  OneDimensionOptions o;
  o.lower = lower;
  o.upper = upper;
  o.step = 0.2;
  o.tolerance = 0.01;
  return o;
}

TEST(MinimiseOneDimension, FindsTheMinimumOfAParabolaFromEitherSide) {
  for (double x0 : {-4.0, 2.0, 0.35, 4.9}) {
    Counted parabola{[](double x) { return (x - 0.3) * (x - 0.3); }};
    const OneDimensionResult r = minimise(parabola, x0, interval(-5.0, 5.0));
    ASSERT_TRUE(r.ok) << r.message;
    EXPECT_NEAR(r.x, 0.3, 0.01) << x0;
    EXPECT_EQ(parabola.batch_sizes.front(), 2u);  // x0 -/+ step together
    EXPECT_LE(r.evaluations, 30) << x0;
    EXPECT_EQ(r.evaluations, [&] {
      size_t n = 0;
      for (size_t b : parabola.batch_sizes) n += b;
      return static_cast<int>(n);
    }());
  }
}

TEST(MinimiseOneDimension, StopsAtABoundWhenTheCostFallsTowardIt) {
  Counted rising{[](double x) { return x; }};
  const OneDimensionResult r = minimise(rising, 2.0, interval(0.0, 3.0));
  ASSERT_TRUE(r.ok);
  EXPECT_NEAR(r.x, 0.0, 0.01);
  EXPECT_GE(r.x, 0.0);
}

TEST(MinimiseOneDimension, LandsOnTheLowestStepOfAStaircase) {
  // Piecewise constant, lowest (0) on [0.5, 0.6): no gradient anywhere.
  Counted stairs{[](double x) {
    const double level = std::floor(10.0 * x) / 10.0;
    return (level - 0.5) * (level - 0.5);
  }};
  const OneDimensionResult r = minimise(stairs, -1.3, interval(-3.0, 3.0));
  ASSERT_TRUE(r.ok);
  EXPECT_EQ(r.cost, 0.0) << r.x;
  EXPECT_GE(r.x, 0.5);
  EXPECT_LT(r.x, 0.6);
}

TEST(MinimiseOneDimension, PointsThatCannotBeEvaluatedAreAvoided) {
  Counted fails_above_one{[](double x) {
    return x > 1.0 ? std::numeric_limits<double>::infinity() : (x - 0.8) * (x - 0.8);
  }};
  const OneDimensionResult r = minimise(fails_above_one, 0.0, interval(-2.0, 2.0));
  ASSERT_TRUE(r.ok);
  EXPECT_NEAR(r.x, 0.8, 0.01);
  Counted never{[](double) { return std::nan(""); }};
  const OneDimensionResult none = minimise(never, 0.0, interval(-1.0, 1.0));
  EXPECT_FALSE(none.ok);
}

TEST(MinimiseOneDimension, NeverReturnsAPointWorseThanTheStart) {
  Counted v{[](double x) { return std::abs(x - 1.0); }};
  const OneDimensionResult r = minimise(v, 1.0, interval(0.0, 2.0));
  EXPECT_EQ(r.x, 1.0);
  EXPECT_EQ(r.cost, 0.0);
  OneDimensionOptions few = interval(-100.0, 100.0);
  few.max_evaluations = 3;
  Counted far{[](double x) { return (x - 90.0) * (x - 90.0); }};
  const OneDimensionResult stopped = minimise(far, 0.0, few);
  EXPECT_LE(stopped.cost, 90.0 * 90.0);
  EXPECT_NE(stopped.message.find("no bracket"), std::string::npos) << stopped.message;
}

TEST(MinimiseOneDimension, BadOptionsAreRefused) {
  Counted f{[](double x) { return x * x; }};
  OneDimensionOptions o = interval(0.0, 1.0);
  EXPECT_THROW(minimise(f, 2.0, o), std::invalid_argument);  // start outside
  o.step = 0.0;
  EXPECT_THROW(minimise(f, 0.5, o), std::invalid_argument);
  o = interval(0.0, 1.0);
  o.tolerance = -1.0;
  EXPECT_THROW(minimise(f, 0.5, o), std::invalid_argument);
}

}  // namespace
}  // namespace identify
}  // namespace flagella
