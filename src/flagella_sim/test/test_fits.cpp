// Tests of the trajectory fitting helpers (outputs/fits.h) against independently known truth:
// synthetic lines/circles with known parameters, noise-derived statistical tolerances, angles
// wrapped with atan2, and rotations built with Eigen.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include "flagella_sim/outputs/fits.h"

namespace flagella {
namespace {

constexpr double kExactTol = 1e-10;    // for noise-free data (round-off only)
constexpr double kNumSigmas = 5.0;     // statistical tolerances: this many standard errors
constexpr unsigned kSeed = 20240611u;  // fixed seed: deterministic test
constexpr double kPi = M_PI;

// ---------------------------------------------------------------------------------------------
// fitLine
// ---------------------------------------------------------------------------------------------

TEST(FitLine, RecoversExactLine) {
  constexpr double kSlope = -2.75, kIntercept = 4.125;
  std::vector<double> x, y;
  for (int i = 0; i < 17; ++i) {
    x.push_back(0.3 * i - 1.7);
    y.push_back(kSlope * x.back() + kIntercept);
  }
  const LinearFit fit = fitLine(x, y);
  EXPECT_NEAR(fit.slope, kSlope, kExactTol);
  EXPECT_NEAR(fit.intercept, kIntercept, kExactTol);
  EXPECT_NEAR(fit.r_squared, 1.0, kExactTol);
}

TEST(FitLine, TwoPointsAndConstantY) {
  const LinearFit two = fitLine({1.0, 3.0}, {2.0, 6.0});
  EXPECT_NEAR(two.slope, 2.0, kExactTol);
  EXPECT_NEAR(two.intercept, 0.0, kExactTol);
  EXPECT_NEAR(two.r_squared, 1.0, kExactTol);

  const LinearFit flat = fitLine({0.0, 1.0, 2.0}, {5.0, 5.0, 5.0});
  EXPECT_NEAR(flat.slope, 0.0, kExactTol);
  EXPECT_NEAR(flat.intercept, 5.0, kExactTol);
  EXPECT_NEAR(flat.r_squared, 1.0, kExactTol);
}

TEST(FitLine, NoisyLineStatistics) {
  constexpr double kSlope = 0.7, kIntercept = -1.2, kSigma = 0.3;
  constexpr int kN = 500;
  constexpr double kXMax = 10.0;
  std::mt19937 rng(kSeed);
  std::normal_distribution<double> noise(0.0, kSigma);
  std::vector<double> x, y;
  for (int i = 0; i < kN; ++i) {
    x.push_back(kXMax * i / (kN - 1));
    y.push_back(kSlope * x.back() + kIntercept + noise(rng));
  }
  const LinearFit fit = fitLine(x, y);

  // Independent least-squares solution (Eigen QR on the design matrix [x 1]).
  Eigen::MatrixXd a(kN, 2);
  Eigen::VectorXd b(kN);
  for (int i = 0; i < kN; ++i) {
    a.row(i) << x[i], 1.0;
    b(i) = y[i];
  }
  const Eigen::Vector2d ls = a.colPivHouseholderQr().solve(b);
  EXPECT_NEAR(fit.slope, ls(0), kExactTol);
  EXPECT_NEAR(fit.intercept, ls(1), kExactTol);

  // Textbook standard errors of the OLS estimates for known noise sigma.
  double mean_x = 0.0;
  for (double v : x) mean_x += v;
  mean_x /= kN;
  double sxx = 0.0;
  for (double v : x) sxx += (v - mean_x) * (v - mean_x);
  const double se_slope = kSigma / std::sqrt(sxx);
  const double se_intercept = kSigma * std::sqrt(1.0 / kN + mean_x * mean_x / sxx);
  EXPECT_NEAR(fit.slope, kSlope, kNumSigmas * se_slope);
  EXPECT_NEAR(fit.intercept, kIntercept, kNumSigmas * se_intercept);

  // r^2 from its definition 1 - SS_res / SS_tot with the fitted line.
  double mean_y = 0.0;
  for (double v : y) mean_y += v;
  mean_y /= kN;
  double ss_res = 0.0, ss_tot = 0.0;
  for (int i = 0; i < kN; ++i) {
    const double r = y[i] - (fit.slope * x[i] + fit.intercept);
    ss_res += r * r;
    ss_tot += (y[i] - mean_y) * (y[i] - mean_y);
  }
  EXPECT_NEAR(fit.r_squared, 1.0 - ss_res / ss_tot, kExactTol);

  // Expected r^2 = signal variance / (signal variance + noise variance). The sample noise
  // variance has relative standard deviation sqrt(2 / N); propagate it to r^2.
  const double signal_var = kSlope * kSlope * sxx / kN;
  const double noise_var = kSigma * kSigma;
  const double expected_r2 = signal_var / (signal_var + noise_var);
  const double se_r2 = expected_r2 * (1.0 - expected_r2) * std::sqrt(2.0 / kN);
  EXPECT_NEAR(fit.r_squared, expected_r2, kNumSigmas * se_r2);
  EXPECT_LT(fit.r_squared, 1.0);
}

TEST(FitLine, ThrowsOnBadInput) {
  EXPECT_THROW(fitLine({1.0, 2.0}, {1.0}), std::invalid_argument);
  EXPECT_THROW(fitLine({1.0}, {1.0}), std::invalid_argument);
  EXPECT_THROW(fitLine({}, {}), std::invalid_argument);
  EXPECT_THROW(fitLine({2.0, 2.0, 2.0}, {1.0, 2.0, 3.0}), std::invalid_argument);
  EXPECT_THROW(fitLine({0.0, 0.0}, {1.0, 2.0}), std::invalid_argument);
  EXPECT_THROW(fitLine({0.0, NAN}, {1.0, 2.0}), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------
// fitCircle
// ---------------------------------------------------------------------------------------------

const Eigen::Vector2d kCenter(1.3, -0.7);
constexpr double kRadius = 2.5;

std::vector<double> arcAngles(double start, double span, int n, bool closed) {
  std::vector<double> t;
  const int divisions = closed ? n : n - 1;  // a full circle must not repeat its first point
  for (int i = 0; i < n; ++i) t.push_back(start + span * i / divisions);
  return t;
}

std::vector<Eigen::Vector2d> circlePoints(const std::vector<double>& angles, double sigma,
                                          std::mt19937* rng) {
  std::normal_distribution<double> noise(0.0, sigma > 0.0 ? sigma : 1.0);
  std::vector<Eigen::Vector2d> pts;
  for (double t : angles) {
    Eigen::Vector2d p = kCenter + kRadius * Eigen::Vector2d(std::cos(t), std::sin(t));
    if (sigma > 0.0) p += Eigen::Vector2d(noise(*rng), noise(*rng));
    pts.push_back(p);
  }
  return pts;
}

// Linearised standard deviations of (cx, cy, r) for isotropic noise sigma per coordinate: the
// geometric residual has Jacobian rows [-cos t, -sin t, -1] at the truth, so
// cov = sigma^2 (J^T J)^-1.
Eigen::Vector3d circleStdDev(const std::vector<double>& angles, double sigma) {
  Eigen::Matrix3d jtj = Eigen::Matrix3d::Zero();
  for (double t : angles) {
    const Eigen::Vector3d row(-std::cos(t), -std::sin(t), -1.0);
    jtj += row * row.transpose();
  }
  return (sigma * sigma * jtj.inverse()).diagonal().cwiseSqrt();
}

// Gradient of 0.5 * sum (|p - c| - r)^2 w.r.t. (c, r): zero at a geometric least-squares fit.
Eigen::Vector3d geometricGradient(const std::vector<Eigen::Vector2d>& pts, const CircleFit& fit) {
  Eigen::Vector3d g = Eigen::Vector3d::Zero();
  for (const Eigen::Vector2d& p : pts) {
    const Eigen::Vector2d diff = p - fit.center;
    const double d = diff.norm();
    const double res = d - fit.radius;
    g.head<2>() -= res * diff / d;
    g(2) -= res;
  }
  return g;
}

void expectNoNaN(const CircleFit& fit) {
  EXPECT_TRUE(fit.center.allFinite());
  EXPECT_TRUE(std::isfinite(fit.radius));
  EXPECT_TRUE(std::isfinite(fit.rms_residual));
}

TEST(FitCircle, ExactPointsFullAndPartialArc) {
  for (double span : {2.0 * kPi, kPi / 3.0}) {
    const bool closed = span > kPi;
    const auto pts = circlePoints(arcAngles(0.4, span, 25, closed), 0.0, nullptr);
    const CircleFit fit = fitCircle(pts);
    ASSERT_TRUE(fit.valid) << "span " << span;
    EXPECT_NEAR(fit.center.x(), kCenter.x(), kExactTol);
    EXPECT_NEAR(fit.center.y(), kCenter.y(), kExactTol);
    EXPECT_NEAR(fit.radius, kRadius, kExactTol);
    EXPECT_NEAR(fit.rms_residual, 0.0, kExactTol);
  }
}

TEST(FitCircle, ThreePointsGiveCircumcircle) {
  const auto pts = circlePoints({0.1, 1.9, 4.0}, 0.0, nullptr);
  const CircleFit fit = fitCircle(pts);
  ASSERT_TRUE(fit.valid);
  EXPECT_NEAR(fit.center.x(), kCenter.x(), kExactTol);
  EXPECT_NEAR(fit.center.y(), kCenter.y(), kExactTol);
  EXPECT_NEAR(fit.radius, kRadius, kExactTol);
}

void checkNoisyArc(double span, bool closed) {
  constexpr double kSigma = 0.01;
  constexpr int kN = 200;
  std::mt19937 rng(kSeed);
  const std::vector<double> angles = arcAngles(0.4, span, kN, closed);
  const auto pts = circlePoints(angles, kSigma, &rng);
  const CircleFit fit = fitCircle(pts);
  ASSERT_TRUE(fit.valid);
  expectNoNaN(fit);

  const Eigen::Vector3d sd = circleStdDev(angles, kSigma);
  EXPECT_NEAR(fit.center.x(), kCenter.x(), kNumSigmas * sd(0));
  EXPECT_NEAR(fit.center.y(), kCenter.y(), kNumSigmas * sd(1));
  EXPECT_NEAR(fit.radius, kRadius, kNumSigmas * sd(2));

  // The radial noise component has std sigma; the fit absorbs 3 degrees of freedom, and the
  // sample variance has relative standard deviation sqrt(2 / N).
  const double expected_rms = kSigma * std::sqrt((kN - 3.0) / kN);
  EXPECT_NEAR(fit.rms_residual, expected_rms, kNumSigmas * expected_rms / std::sqrt(2.0 * kN));

  // Gauss-Newton refinement converged to a stationary point of the geometric cost (the Kasa
  // estimate alone is not one for noisy partial arcs).
  const double grad_scale = std::sqrt(static_cast<double>(kN)) * fit.rms_residual;
  EXPECT_LT(geometricGradient(pts, fit).norm(), 1e-8 * grad_scale);
}

TEST(FitCircle, NoisyFullCircle) { checkNoisyArc(2.0 * kPi, true); }

TEST(FitCircle, NoisySixtyDegreeArc) { checkNoisyArc(kPi / 3.0, false); }

TEST(FitCircle, DegenerateInputIsInvalid) {
  const std::vector<std::vector<Eigen::Vector2d>> cases = {
      {},
      {Eigen::Vector2d(0, 0)},
      {Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 1)},
      // exactly collinear
      {Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 2), Eigen::Vector2d(2, 4), Eigen::Vector2d(3, 6)},
      // collinear up to round-off
      {Eigen::Vector2d(0.1, 0.3), Eigen::Vector2d(0.2, 0.6 + 1e-15), Eigen::Vector2d(0.3, 0.9)},
      // all points identical
      {Eigen::Vector2d(2, 2), Eigen::Vector2d(2, 2), Eigen::Vector2d(2, 2)},
      // non-finite
      {Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 0), Eigen::Vector2d(NAN, 1)},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const CircleFit fit = fitCircle(cases[i]);
    EXPECT_FALSE(fit.valid) << "case " << i;
    expectNoNaN(fit);
  }
}

// ---------------------------------------------------------------------------------------------
// unwrapAngles
// ---------------------------------------------------------------------------------------------

void checkUnwrap(double start, double step, int n) {
  std::vector<double> truth, wrapped;
  for (int i = 0; i < n; ++i) {
    truth.push_back(start + step * i);
    wrapped.push_back(std::atan2(std::sin(truth.back()), std::cos(truth.back())));
  }
  const std::vector<double> out = unwrapAngles(wrapped);
  ASSERT_EQ(out.size(), truth.size());
  // The unwrapped sequence starts at the wrapped first angle, so it differs from the truth by a
  // constant multiple of 2 pi.
  const double offset = wrapped[0] - truth[0];
  EXPECT_NEAR(std::remainder(offset, 2.0 * kPi), 0.0, kExactTol);
  for (int i = 0; i < n; ++i) EXPECT_NEAR(out[i], truth[i] + offset, 1e-9) << "i = " << i;
}

TEST(UnwrapAngles, LinearlyIncreasingAngle) { checkUnwrap(-1.0, 0.37, 300); }

TEST(UnwrapAngles, LargeStepsAndDecreasing) {
  checkUnwrap(0.5, 3.0, 100);   // steps close to (but below) pi
  checkUnwrap(5.0, -2.2, 100);  // decreasing, first angle outside (-pi, pi]
}

TEST(UnwrapAngles, EdgeCases) {
  EXPECT_TRUE(unwrapAngles({}).empty());
  const std::vector<double> one = unwrapAngles({7.0});
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one[0], 7.0);
  const std::vector<double> smooth = {0.0, 0.5, 1.0, 1.5, 1.0};
  const std::vector<double> out = unwrapAngles(smooth);
  for (std::size_t i = 0; i < smooth.size(); ++i) EXPECT_NEAR(out[i], smooth[i], kExactTol);
}

// ---------------------------------------------------------------------------------------------
// quaternionFromFrame
// ---------------------------------------------------------------------------------------------

Eigen::Quaterniond randomRotation(std::mt19937* rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::Quaterniond q(normal(*rng), normal(*rng), normal(*rng), normal(*rng));
  q.normalize();
  return q;
}

void expectRotation(const Eigen::Matrix3d& r) {
  EXPECT_LT((r.transpose() * r - Eigen::Matrix3d::Identity()).norm(), kExactTol);
  EXPECT_NEAR(r.determinant(), 1.0, kExactTol);
}

TEST(QuaternionFromFrame, RoundTripRandomRotations) {
  std::mt19937 rng(kSeed);
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Quaterniond truth = randomRotation(&rng);
    const Eigen::Matrix3d r = truth.toRotationMatrix();
    const Eigen::Quaterniond q = quaternionFromFrame(r.col(0), r.col(1), r.col(2));
    EXPECT_NEAR(q.norm(), 1.0, kExactTol);
    EXPECT_GE(q.w(), 0.0);
    EXPECT_LT((q.toRotationMatrix() - r).norm(), kExactTol) << "trial " << trial;
    // Same rotation: q = +-truth.
    EXPECT_NEAR(std::abs(q.dot(truth)), 1.0, kExactTol);
  }
}

TEST(QuaternionFromFrame, IdentityAndHalfTurn) {
  const Eigen::Quaterniond id = quaternionFromFrame(
      Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ());
  EXPECT_NEAR(id.w(), 1.0, kExactTol);
  EXPECT_NEAR(id.vec().norm(), 0.0, kExactTol);
  // 180 degrees about z: w = 0, the sign convention must still produce a valid rotation.
  const Eigen::Quaterniond half = quaternionFromFrame(
      -Eigen::Vector3d::UnitX(), -Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ());
  EXPECT_NEAR(half.w(), 0.0, kExactTol);
  EXPECT_NEAR(std::abs(half.z()), 1.0, kExactTol);
}

TEST(QuaternionFromFrame, SlightlyNonOrthogonalFrame) {
  constexpr double kPerturbation = 1e-4;
  std::mt19937 rng(kSeed + 1);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (int trial = 0; trial < 50; ++trial) {
    const Eigen::Matrix3d r = randomRotation(&rng).toRotationMatrix();
    Eigen::Matrix3d e;
    for (int k = 0; k < 9; ++k) e(k) = normal(rng);
    const Eigen::Matrix3d m = r + kPerturbation * e;
    const Eigen::Quaterniond q = quaternionFromFrame(m.col(0), m.col(1), m.col(2));
    EXPECT_NEAR(q.norm(), 1.0, kExactTol);
    EXPECT_GE(q.w(), 0.0);
    const Eigen::Matrix3d rq = q.toRotationMatrix();
    expectRotation(rq);
    // Projection onto SO(3) moves at most by the size of the perturbation (first order).
    EXPECT_LT((rq - r).norm(), 2.0 * kPerturbation * e.norm()) << "trial " << trial;
    // And it is at least as close to the (column-normalised) input as the original rotation.
    Eigen::Matrix3d mn = m;
    mn.colwise().normalize();
    EXPECT_LE((rq - mn).norm(), (r - mn).norm() + kExactTol) << "trial " << trial;
  }
}

TEST(QuaternionFromFrame, ThrowsOnDegenerateFrame) {
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX(), y = Eigen::Vector3d::UnitY();
  EXPECT_THROW(quaternionFromFrame(x, y, Eigen::Vector3d::Zero()), std::invalid_argument);
  EXPECT_THROW(quaternionFromFrame(x, x, y), std::invalid_argument);
  EXPECT_THROW(quaternionFromFrame(x, y, -Eigen::Vector3d::UnitZ()), std::invalid_argument);
  EXPECT_THROW(quaternionFromFrame(x, y, Eigen::Vector3d(0, 0, NAN)), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------
// rootMeanSquare
// ---------------------------------------------------------------------------------------------

TEST(RootMeanSquare, KnownValues) {
  EXPECT_EQ(rootMeanSquare({}), 0.0);
  EXPECT_NEAR(rootMeanSquare({3.0, -4.0}), std::sqrt(12.5), kExactTol);
  EXPECT_NEAR(rootMeanSquare({-2.0, -2.0, -2.0}), 2.0, kExactTol);
  // sin over whole periods has RMS 1/sqrt(2).
  std::vector<double> s;
  constexpr int kSamples = 1000;
  for (int i = 0; i < kSamples; ++i) s.push_back(std::sin(2.0 * kPi * 3.0 * i / kSamples));
  EXPECT_NEAR(rootMeanSquare(s), 1.0 / std::sqrt(2.0), kExactTol);
}

}  // namespace
}  // namespace flagella
