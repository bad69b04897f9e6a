// The rotating chord predictor (solver/chord_predictor.h, docs/model.md 1.10) against closed-form
// motions: exact on a steady circle and on a steadily growing spiral in a tilted plane (where the
// linear 2 v_last - v_prev misses by the chord turn squared), the linear value on a straight line,
// and the linear fallback for a zero chord or a turn of more than 60 deg per step.
#include <gtest/gtest.h>

#include <cmath>

#include "flagella_sim/solver/chord_predictor.h"

namespace flagella {
namespace {

// Position k of a point turning by `angle` per step about a tilted axis, its radius growing by
// the factor `growth` per step.
Vec3 spiralPoint(int k, double angle, double growth) {
  const Vec3 axis = Vec3(0.3, -0.5, 0.8).normalized();
  const Vec3 e1 = axis.unitOrthogonal(), e2 = axis.cross(e1);
  const double r = 2e-3 * std::pow(growth, k);
  return Vec3(0.01, 0.02, -0.03) + r * (std::cos(k * angle) * e1 + std::sin(k * angle) * e2);
}

TEST(ChordPredictor, ExactOnSteadyCirclesAndSpirals) {
  const double dt = 0.01;
  for (double angle : {0.05, 0.3, 0.9}) {
    for (double growth : {1.0, 1.02, 0.97}) {
      SCOPED_TRACE("angle " + std::to_string(angle) + " growth " + std::to_string(growth));
      const Vec3 v_prev = (spiralPoint(1, angle, growth) - spiralPoint(0, angle, growth)) / dt;
      const Vec3 v_last = (spiralPoint(2, angle, growth) - spiralPoint(1, angle, growth)) / dt;
      const Vec3 truth = (spiralPoint(3, angle, growth) - spiralPoint(2, angle, growth)) / dt;
      const Vec3 predicted = rotatingChordPrediction(v_prev, v_last);
      EXPECT_LT((predicted - truth).norm(), 1e-12 * truth.norm());
      // the linear extrapolation misses by about angle^2 |v|: the test tells them apart
      const Vec3 linear = 2.0 * v_last - v_prev;
      EXPECT_GT((linear - truth).norm(), 0.2 * angle * angle * truth.norm());
    }
  }
}

TEST(ChordPredictor, LinearOnAStraightLineAndForZeroOrLargeTurns) {
  const Vec3 v(1e-3, -2e-3, 5e-4);
  EXPECT_LT((rotatingChordPrediction(v, v) - v).norm(), 1e-15);
  const Vec3 zero = Vec3::Zero();
  EXPECT_EQ(rotatingChordPrediction(zero, v), 2.0 * v - zero);
  EXPECT_EQ(rotatingChordPrediction(v, zero), 2.0 * zero - v);
  // 90 deg per step: beyond the 60 deg the rotation is trusted for
  const Vec3 a(1.0, 0.0, 0.0), b(0.0, 1.0, 0.0);
  EXPECT_EQ(rotatingChordPrediction(a, b), 2.0 * b - a);
  // 50 deg per step: still a rotation (the next chord at 100 deg from a)
  const double t = 50.0 * M_PI / 180.0;
  const Vec3 c(std::cos(t), std::sin(t), 0.0);
  const Vec3 next = rotatingChordPrediction(a, c);
  EXPECT_NEAR(next.x(), std::cos(2 * t), 1e-14);
  EXPECT_NEAR(next.y(), std::sin(2 * t), 1e-14);
}

}  // namespace
}  // namespace flagella
