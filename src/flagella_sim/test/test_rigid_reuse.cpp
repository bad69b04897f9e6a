// The rigid reuse of a factored RSS matrix (docs/model.md 4.4): the best-fit rigid motion
// (Kabsch) against known motions, and the isotropy of the regularized Stokeslet that makes a
// rotated factorisation exact: forces from the reused solver equal those of a solver built at the
// moved nodes, while a deformation beyond the tolerance forces a rebuild.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "flagella_sim/core/rigid_fit.h"
#include "flagella_sim/hydro/rss_solver.h"

namespace flagella {
namespace {

using rss::Polyline;

Polyline helixPolyline(int m) {
  Polyline nodes;
  for (int p = 0; p < m; ++p) {
    const double s = 0.35 * p;
    nodes.push_back(Vec3(0.3 * std::cos(s), 0.3 * std::sin(s), 0.08 * s + 0.01 * std::sin(3 * s)));
  }
  return nodes;
}

Mat3 rotationAbout(const Vec3& axis, double angle) {
  return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

Polyline moved(const Polyline& y, const Mat3& R, const Vec3& c) {
  Polyline x;
  for (const Vec3& p : y) x.push_back(R * p + c);
  return x;
}

TEST(RigidFit, RecoversAKnownRotationAndTranslation) {
  const Polyline y = helixPolyline(30);
  const Mat3 R = rotationAbout(Vec3(0.3, -1.0, 0.4), 2.1);
  const Vec3 c(0.5, -0.2, 1.5);
  const RigidFit fit = bestRigidFit(y, moved(y, R, c));
  EXPECT_LT((fit.rotation - R).norm(), 1e-12);
  EXPECT_LT((fit.translation - c).norm(), 1e-12);
  EXPECT_LT(fit.deviation, 1e-12);
  EXPECT_NEAR(fit.rotation.determinant(), 1.0, 1e-12);
}

TEST(RigidFit, AMirrorImageIsNotARotation) {
  // A reflection fits no proper rotation: the fit stays a rotation and reports the deviation.
  const Polyline y = helixPolyline(30);
  Polyline mirrored;
  for (const Vec3& p : y) mirrored.push_back(Vec3(p.x(), -p.y(), p.z()));
  const RigidFit fit = bestRigidFit(y, mirrored);
  EXPECT_NEAR(fit.rotation.determinant(), 1.0, 1e-12);
  EXPECT_GT(fit.deviation, 0.05);
}

TEST(RigidFit, DeviationIsTheLargestNodeDisplacementBeyondTheMotion) {
  // One node displaced by d along the helix's axis from an otherwise rigid motion: the fit
  // spreads part of it over the others, so the deviation lies between (1 - 1/n) d and d.
  const Polyline y = helixPolyline(40);
  const Mat3 R = rotationAbout(Vec3(1, 1, 0), 0.7);
  Polyline x = moved(y, R, Vec3(0.1, 0.2, 0.3));
  const double d = 1e-4;
  x[17] += d * Vec3(0, 0, 1);
  const RigidFit fit = bestRigidFit(y, x);
  EXPECT_LE(fit.deviation, d * (1 + 1e-9));
  EXPECT_GE(fit.deviation, d * (1.0 - 1.0 / 40) * 0.95);
  EXPECT_THROW(bestRigidFit(y, Polyline(y.begin(), y.end() - 1)), std::invalid_argument);
}

TEST(RssRigidReuse, RotatedFactorisationGivesTheForcesOfARebuiltOne) {
  const Polyline y = helixPolyline(36);
  const rss::Segments segments = rss::chainSegments(36);
  const double eps = 0.03, mu = 1.2;
  rss::RssSolver reused(y, segments, eps, mu);
  const Mat3 R = rotationAbout(Vec3(-0.2, 0.5, 1.0), 0.9);
  const Polyline x = moved(y, R, Vec3(0.3, -0.4, 0.2));
  ASSERT_TRUE(reused.updateOrReuse(x, segments, eps, 1.7, 1e-6));
  EXPECT_LT(reused.lastDeviation(), 1e-12);
  const rss::RssSolver rebuilt(x, segments, eps, 1.7);
  std::mt19937 rng(4);
  std::normal_distribution<double> g;
  const VecX U = VecX::NullaryExpr(3 * 36, [&] { return g(rng); });
  const VecX expected = rebuilt.nodalForces(U);
  EXPECT_LT((reused.nodalForces(U) - expected).norm(), 1e-10 * expected.norm());
  EXPECT_LT((reused.matrix() - rebuilt.matrix()).norm(), 1e-10 * rebuilt.matrix().norm());
  EXPECT_LT((reused.dragMatrix() - rebuilt.dragMatrix()).norm(),
            1e-9 * rebuilt.dragMatrix().norm());
}

TEST(RssRigidReuse, DeformationBeyondTheToleranceRebuilds) {
  const Polyline y = helixPolyline(36);
  const rss::Segments segments = rss::chainSegments(36);
  const double eps = 0.03;
  rss::RssSolver solver(y, segments, eps, 1.0);
  Polyline x = moved(y, rotationAbout(Vec3(0, 0, 1), 0.2), Vec3::Zero());
  x[10] += Vec3(0, 0, 2e-3 * eps);  // about 2e-3 eps off the rigid motion
  EXPECT_TRUE(solver.updateOrReuse(x, segments, eps, 1.0, 1e-2));
  EXPECT_GT(solver.lastDeviation(), 1e-3 * eps);
  EXPECT_FALSE(solver.updateOrReuse(x, segments, eps, 1.0, 1e-3));  // rebuilt at x
  EXPECT_EQ(solver.lastDeviation(), 0.0);
  const rss::RssSolver rebuilt(x, segments, eps, 1.0);
  const VecX U = VecX::Ones(3 * 36);
  EXPECT_LT((solver.nodalForces(U) - rebuilt.nodalForces(U)).norm(),
            1e-12 * rebuilt.nodalForces(U).norm());
  // tolerance 0 and a different eps always rebuild
  EXPECT_FALSE(solver.updateOrReuse(x, segments, eps, 1.0, 0.0));
  EXPECT_FALSE(solver.updateOrReuse(x, segments, 1.1 * eps, 1.0, 1.0));
}

}  // namespace
}  // namespace flagella
