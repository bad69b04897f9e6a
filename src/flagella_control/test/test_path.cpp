// Path geometry (path.h, heading.h) and path descriptions (path_spec.h) against closed-form truth.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "flagella_control/heading.h"
#include "flagella_control/path.h"
#include "flagella_control/path_spec.h"
#include "flagella_sim/core/units.h"

namespace fc = flagella::control;
namespace units = flagella::units;
using fc::Path;
using fc::Vec2;

namespace {

constexpr double kTol = 1e-12;

double angleDiff(double a, double b) { return std::abs(fc::wrapAngle(a - b)); }

// The error message of a pathSpecFromYaml call that must fail ("" if it did not throw).
std::string specError(const std::string& yaml) {
  try {
    fc::pathSpecFromYaml(YAML::Load(yaml));
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

Path rectangle(double w, double h, bool left) {
  const double s = left ? 1.0 : -1.0;
  return Path::polyline({{0, 0}, {w, 0}, {w, s * h}, {0, s * h}}, true);
}

}  // namespace

// ---- lengths ----------------------------------------------------------------------------------

TEST(PathGeometry, LengthsOfBasicShapes) {
  const Path open = Path::polyline({{0, 0}, {3, 0}, {3, 4}}, false);
  EXPECT_NEAR(open.length(), 7.0, kTol);
  EXPECT_FALSE(open.closed());
  EXPECT_EQ(open.elements().size(), 2u);

  // Closing a polyline adds the segment back to the first point.
  const Path closed = Path::polyline({{0, 0}, {3, 0}, {3, 4}}, true);
  EXPECT_NEAR(closed.length(), 12.0, kTol);
  EXPECT_TRUE(closed.closed());
  EXPECT_EQ(closed.elements().size(), 3u);

  EXPECT_NEAR(rectangle(0.3, 0.2, true).length(), 1.0, kTol);
  const double a = 0.25;
  const Path triangle = Path::polyline({{0, 0}, {a, 0}, {a / 2, a * std::sqrt(3.0) / 2}}, true);
  EXPECT_NEAR(triangle.length(), 3 * a, 1e-12);

  const Path circle = Path::circle({1, 2}, 0.3, 0.2, true);
  EXPECT_NEAR(circle.length(), 2 * M_PI * 0.2, kTol);
  EXPECT_TRUE(circle.closed());

  // s_start of each element is the running sum of the lengths before it.
  EXPECT_NEAR(closed.elements()[0].s_start, 0.0, kTol);
  EXPECT_NEAR(closed.elements()[1].s_start, 3.0, kTol);
  EXPECT_NEAR(closed.elements()[2].s_start, 7.0, kTol);
}

TEST(PathGeometry, PolylineRejectsBadPoints) {
  EXPECT_THROW(Path::polyline({{0, 0}}, false), std::invalid_argument);
  EXPECT_THROW(Path::polyline({{0, 0}, {1, 0}, {1, 0}}, false), std::invalid_argument);
  EXPECT_THROW(Path::polyline({{0, 0}, {NAN, 0}}, false), std::invalid_argument);
  EXPECT_THROW(Path::circle({0, 0}, 0.0, -1.0, true), std::invalid_argument);
  EXPECT_THROW(Path::circle({0, 0}, 0.0, 0.0, true), std::invalid_argument);
}

// ---- at(s) ------------------------------------------------------------------------------------

TEST(PathGeometry, AtOnOpenPolylineClampsToTheEnds) {
  const Path p = Path::polyline({{0, 0}, {3, 0}, {3, 4}}, false);
  fc::PathPoint q = p.at(1.5);
  EXPECT_NEAR(q.position.x(), 1.5, kTol);
  EXPECT_NEAR(q.position.y(), 0.0, kTol);
  EXPECT_NEAR(q.tangent, 0.0, kTol);
  EXPECT_EQ(q.curvature, 0.0);
  EXPECT_EQ(q.element, 0);

  q = p.at(4.0);
  EXPECT_NEAR(q.position.x(), 3.0, kTol);
  EXPECT_NEAR(q.position.y(), 1.0, kTol);
  EXPECT_NEAR(q.tangent, M_PI / 2, kTol);
  EXPECT_EQ(q.element, 1);

  q = p.at(-2.0);  // before the start: the start
  EXPECT_NEAR((q.position - Vec2(0, 0)).norm(), 0.0, kTol);
  EXPECT_NEAR(q.tangent, 0.0, kTol);
  q = p.at(50.0);  // past the end: the end
  EXPECT_NEAR((q.position - Vec2(3, 4)).norm(), 0.0, kTol);
  EXPECT_NEAR(q.tangent, M_PI / 2, kTol);
  EXPECT_EQ(q.element, 1);
}

TEST(PathGeometry, AtOnClosedPathWraps) {
  const Path r = rectangle(0.3, 0.2, true);
  const double L = r.length();
  for (double s : {0.05, 0.3, 0.31, 0.55, 0.77, 0.99}) {
    const fc::PathPoint a = r.at(s), b = r.at(s + L), c = r.at(s - L), d = r.at(s + 3 * L);
    EXPECT_NEAR((a.position - b.position).norm(), 0.0, 1e-12) << s;
    EXPECT_NEAR((a.position - c.position).norm(), 0.0, 1e-12) << s;
    EXPECT_NEAR((a.position - d.position).norm(), 0.0, 1e-12) << s;
    EXPECT_NEAR(angleDiff(a.tangent, b.tangent), 0.0, 1e-12) << s;
  }
  // The four sides: +x, +y, -x, -y.
  EXPECT_NEAR((r.at(0.1).position - Vec2(0.1, 0)).norm(), 0.0, kTol);
  EXPECT_NEAR((r.at(0.4).position - Vec2(0.3, 0.1)).norm(), 0.0, kTol);
  EXPECT_NEAR(r.at(0.4).tangent, M_PI / 2, kTol);
  EXPECT_NEAR((r.at(0.6).position - Vec2(0.2, 0.2)).norm(), 0.0, kTol);
  EXPECT_NEAR(angleDiff(r.at(0.6).tangent, M_PI), 0.0, kTol);
  EXPECT_NEAR((r.at(0.9).position - Vec2(0.0, 0.1)).norm(), 0.0, kTol);
  EXPECT_NEAR(r.at(0.9).tangent, -M_PI / 2, kTol);
  // Negative s: from the end backwards.
  EXPECT_NEAR((r.at(-0.05).position - Vec2(0.0, 0.05)).norm(), 0.0, 1e-12);
}

TEST(PathGeometry, AtOnCirclesCcwAndCw) {
  const double r = 0.2;
  const Path ccw = Path::circle({0, 0}, 0.0, r, true);  // centre (0, r)
  const Path cw = Path::circle({0, 0}, 0.0, r, false);  // centre (0, -r)
  for (double s = 0.0; s < 2.5 * ccw.length(); s += 0.0371) {
    const double th = s / r;
    const fc::PathPoint a = ccw.at(s);
    EXPECT_NEAR(a.position.x(), r * std::sin(th), 1e-12) << s;
    EXPECT_NEAR(a.position.y(), r - r * std::cos(th), 1e-12) << s;
    EXPECT_NEAR(angleDiff(a.tangent, th), 0.0, 1e-9) << s;
    EXPECT_NEAR(a.curvature, 1.0 / r, 1e-12);
    const fc::PathPoint b = cw.at(s);
    EXPECT_NEAR(b.position.x(), r * std::sin(th), 1e-12) << s;
    EXPECT_NEAR(b.position.y(), -r + r * std::cos(th), 1e-12) << s;
    EXPECT_NEAR(angleDiff(b.tangent, -th), 0.0, 1e-9) << s;
    EXPECT_NEAR(b.curvature, -1.0 / r, 1e-12);
  }
  // A circle that starts elsewhere, heading north: centre to the west for CCW.
  const Path north = Path::circle({1, 1}, M_PI / 2, 0.5, true);
  EXPECT_NEAR((north.elements()[0].center - Vec2(0.5, 1)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((north.at(north.length() / 2).position - Vec2(0, 1)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(angleDiff(north.at(north.length() / 2).tangent, -M_PI / 2), 0.0, 1e-12);
}

// ---- projection -------------------------------------------------------------------------------

TEST(PathGeometry, ProjectOnLinesSignedCrossTrack) {
  const Path east = Path::polyline({{0, 0}, {1, 0}}, false);
  fc::PathProjection p = east.project({0.5, 0.2});
  EXPECT_NEAR(p.s, 0.5, kTol);
  EXPECT_NEAR(p.cross_track, 0.2, kTol);  // left of travel: positive
  EXPECT_NEAR(p.distance, 0.2, kTol);
  p = east.project({0.25, -0.3});
  EXPECT_NEAR(p.s, 0.25, kTol);
  EXPECT_NEAR(p.cross_track, -0.3, kTol);
  EXPECT_NEAR(p.distance, 0.3, kTol);

  const Path west = Path::polyline({{1, 0}, {0, 0}}, false);
  p = west.project({0.5, 0.2});
  EXPECT_NEAR(p.s, 0.5, kTol);
  EXPECT_NEAR(p.cross_track, -0.2, kTol);  // now on the right

  // A diagonal line: offset along the left normal (-sin, cos).
  const double a = 0.6;
  const Vec2 dir(std::cos(a), std::sin(a)), left(-std::sin(a), std::cos(a));
  const Path diag = Path::polyline({{1, 1}, Vec2(1, 1) + 2.0 * dir}, false);
  p = diag.project(Vec2(1, 1) + 0.7 * dir + 0.15 * left);
  EXPECT_NEAR(p.s, 0.7, 1e-12);
  EXPECT_NEAR(p.cross_track, 0.15, 1e-12);
  p = diag.project(Vec2(1, 1) + 1.3 * dir - 0.05 * left);
  EXPECT_NEAR(p.s, 1.3, 1e-12);
  EXPECT_NEAR(p.cross_track, -0.05, 1e-12);

  // Beyond the end of an open path: the end point, the distance to it.
  p = east.project({1.3, 0.4});
  EXPECT_NEAR(p.s, 1.0, kTol);
  EXPECT_NEAR(p.distance, 0.5, kTol);
  EXPECT_NEAR(p.cross_track, 0.5, kTol);  // on the left side of the end tangent
}

TEST(PathGeometry, ProjectOnCirclesInsideOutside) {
  const double r = 0.2;
  const Path ccw = Path::circle({0, 0}, 0.0, r, true);  // centre (0, r), start angle -pi/2
  const Path cw = Path::circle({0, 0}, 0.0, r, false);  // centre (0, -r), start angle +pi/2
  for (double phi : {-2.0, -1.2, -0.3, 0.4, 1.0, 2.5, 3.0}) {
    for (double rho : {0.05, 0.15, 0.25, 0.4}) {
      // CCW: inside is on the left.
      Vec2 q = Vec2(0, r) + rho * Vec2(std::cos(phi), std::sin(phi));
      fc::PathProjection p = ccw.project(q);
      EXPECT_NEAR(p.cross_track, r - rho, 1e-12) << phi << " " << rho;
      double travelled = std::fmod(phi + M_PI / 2 + 4 * M_PI, 2 * M_PI);
      EXPECT_NEAR(p.s, r * travelled, 1e-9) << phi << " " << rho;
      EXPECT_NEAR((p.point.position - (Vec2(0, r) + r * Vec2(std::cos(phi), std::sin(phi)))).norm(),
                  0.0, 1e-12);
      // CW: inside is on the right.
      q = Vec2(0, -r) + rho * Vec2(std::cos(phi), std::sin(phi));
      p = cw.project(q);
      EXPECT_NEAR(p.cross_track, rho - r, 1e-12) << phi << " " << rho;
      travelled = std::fmod(M_PI / 2 - phi + 4 * M_PI, 2 * M_PI);
      EXPECT_NEAR(p.s, r * travelled, 1e-9) << phi << " " << rho;
    }
  }
}

TEST(PathGeometry, WindowedProjectionOnClosedPathIsLapCumulative) {
  const Path r = rectangle(0.3, 0.2, true);
  const double L = r.length();
  const Vec2 q(0.01, -0.005);  // just after the start, slightly right
  fc::PathProjection p = r.project(q, L - 0.05, L + 0.05);
  EXPECT_NEAR(p.s, L + 0.01, 1e-12);
  EXPECT_NEAR(p.cross_track, -0.005, 1e-12);
  EXPECT_EQ(p.point.element, 0);
  // Second and third lap.
  p = r.project(q, 2 * L - 0.05, 2 * L + 0.05);
  EXPECT_NEAR(p.s, 2 * L + 0.01, 1e-12);
  // Window ending before the lap: the nearest point is clipped to the window on the last side.
  p = r.project(q, L - 0.05, L - 0.002);
  EXPECT_NEAR(p.s, L - 0.002, 1e-12);
  EXPECT_EQ(p.point.element, 3);
  EXPECT_NEAR((p.point.position - Vec2(0, 0.002)).norm(), 0.0, 1e-12);
  // A window on one side only ignores a nearer side.
  p = r.project({0.29, 0.19}, 0.0, 0.2);  // nearest overall is the corner area, window on side 0
  EXPECT_NEAR(p.s, 0.2, 1e-12);
  EXPECT_NEAR(p.distance, (Vec2(0.29, 0.19) - Vec2(0.2, 0)).norm(), 1e-12);
  // Whole-lap projection of the same point.
  p = r.project(q);
  EXPECT_NEAR(p.s, 0.01, 1e-12);
  // Empty window.
  p = r.project(q, 0.5, 0.4);
  EXPECT_TRUE(std::isinf(p.distance));

  // An open path clips the window to [0, length].
  const Path open = Path::polyline({{0, 0}, {1, 0}}, false);
  p = open.project({0.9, 0.1}, 0.5, 3.0);
  EXPECT_NEAR(p.s, 0.9, kTol);
  p = open.project({1.5, 0.0}, 0.5, 3.0);
  EXPECT_NEAR(p.s, 1.0, kTol);
  p = open.project({-0.5, 0.0}, -2.0, 0.5);
  EXPECT_NEAR(p.s, 0.0, kTol);

  // Circle: a point near the start, searched around the end of lap 1.
  const Path c = Path::circle({0, 0}, 0.0, 0.2, true);
  p = c.project({0.004, 0.001}, c.length() - 0.05, c.length() + 0.05);
  EXPECT_GT(p.s, c.length());
  EXPECT_NEAR(p.s, c.length() + 0.2 * std::atan2(0.004, 0.2 - 0.001), 1e-9);
}

// Brute force: the nearest of many points sampled in [s_min, s_max] (lap-cumulative on a closed
// path, clipped to [0, length] on an open one).
double bruteForceDistance(const Path& p, const Vec2& q, double s_min, double s_max) {
  if (!p.closed()) {
    s_min = std::clamp(s_min, 0.0, p.length());
    s_max = std::clamp(s_max, 0.0, p.length());
  }
  double best = std::numeric_limits<double>::infinity();
  const int n = 20000;
  for (int i = 0; i <= n; ++i)
    best = std::min(best, (p.at(s_min + (s_max - s_min) * i / n).position - q).norm());
  return best;
}

TEST(PathGeometry, WindowedProjectionIsTheNearestPointOfTheWindow) {
  // A point just behind the start of a circle, inside it; a window ahead of the start. The
  // nearest point of the window is its near (lower) end, not its far end.
  const Path c = Path::circle({0, 0}, 0.0, 0.2, true);  // centre (0, 0.2)
  const double behind = units::degToRad(-5.0);          // 5 degrees before the start
  const Vec2 q =
      Vec2(0, 0.2) + 0.12 * Vec2(std::cos(-M_PI / 2 + behind), std::sin(-M_PI / 2 + behind));
  fc::PathProjection p = c.project(q, 0.05, 0.22);
  EXPECT_NEAR(p.s, 0.05, 1e-12) << "the window end nearer to the point";
  EXPECT_NEAR(p.distance, bruteForceDistance(c, q, 0.05, 0.22), 1e-9);

  // Property: random points and windows on arcs (both senses, partial and full) and lines.
  Path arcs;
  arcs.appendArc({0, 0}, 0.3, -M_PI / 2, 1.5 * M_PI);  // 3/4 of a circle, CCW
  arcs.appendArc({-0.6, 0.0}, 0.3, 0.0, -M_PI);        // then half a circle, CW
  const std::vector<Path> paths = {c, Path::circle({0.3, -0.1}, 1.0, 0.15, false), arcs,
                                   rectangle(0.3, 0.2, true),
                                   Path::polyline({{0, 0}, {0.2, 0}, {0.35, 0.15}}, false)};
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-0.5, 0.7), uw(0.0, 1.0);
  int checked = 0;
  for (const Path& path : paths) {
    for (int k = 0; k < 300; ++k) {
      const Vec2 point(u(rng), u(rng));
      const double s_min = (uw(rng) * 1.5 - 0.2) * path.length();
      const double s_max = s_min + uw(rng) * 0.6 * path.length();
      const fc::PathProjection pr = path.project(point, s_min, s_max);
      const double brute = bruteForceDistance(path, point, s_min, s_max);
      ASSERT_NEAR(pr.distance, brute, 1e-4)
          << "path " << (&path - paths.data()) << " point " << point.transpose() << " window ["
          << s_min << ", " << s_max << "] -> s " << pr.s;
      // The reported point is at the reported arclength, inside the window.
      const double lo = path.closed() ? s_min : std::clamp(s_min, 0.0, path.length());
      const double hi = path.closed() ? s_max : std::clamp(s_max, 0.0, path.length());
      EXPECT_GE(pr.s, lo - 1e-9);
      EXPECT_LE(pr.s, hi + 1e-9);
      EXPECT_NEAR((path.at(pr.s).position - pr.point.position).norm(), 0.0, 1e-9);
      EXPECT_NEAR((pr.point.position - point).norm(), pr.distance, 1e-12);
      ++checked;
    }
  }
  EXPECT_EQ(checked, 1500);
}

// ---- corners ----------------------------------------------------------------------------------

TEST(PathGeometry, TurnAfterCorners) {
  const Path left = rectangle(0.3, 0.2, true);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(left.turnAfter(i), M_PI / 2, 1e-12) << i;
  const Path right = rectangle(0.3, 0.2, false);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(right.turnAfter(i), -M_PI / 2, 1e-12) << i;
  const double a = 0.3;
  const Path tri = Path::polyline({{0, 0}, {a, 0}, {a / 2, a * std::sqrt(3.0) / 2}}, true);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(tri.turnAfter(i), 2 * M_PI / 3, 1e-12) << i;
  const Path tri_right = Path::polyline({{0, 0}, {a, 0}, {a / 2, -a * std::sqrt(3.0) / 2}}, true);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(tri_right.turnAfter(i), -2 * M_PI / 3, 1e-12) << i;

  const Path open = Path::polyline({{0, 0}, {1, 0}, {1, 1}, {2, 2}}, false);
  EXPECT_NEAR(open.turnAfter(0), M_PI / 2, 1e-12);
  EXPECT_NEAR(open.turnAfter(1), -M_PI / 4, 1e-12);
  EXPECT_EQ(open.turnAfter(2), 0.0);   // end of an open path
  EXPECT_EQ(open.turnAfter(-1), 0.0);  // out of range
  EXPECT_EQ(open.turnAfter(7), 0.0);
  // A full circle is smooth at its junction.
  EXPECT_NEAR(Path::circle({0, 0}, 0.0, 0.2, true).turnAfter(0), 0.0, 1e-9);
}

// ---- rigid motion -----------------------------------------------------------------------------

TEST(PathGeometry, TransformedIsARigidMotion) {
  const Vec2 offset(0.7, -1.3);
  const double yaw = 2.1;
  const Eigen::Rotation2Dd R(yaw);
  const std::vector<Path> paths = {
      rectangle(0.3, 0.2, true), Path::polyline({{0, 0}, {0.2, 0}, {0.35, 0.15}, {0.5, 0}}, false),
      Path::circle({0, 0}, 0.0, 0.2, false)};
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.4, 0.6);
  for (const Path& p : paths) {
    const Path t = p.transformed(offset, yaw);
    EXPECT_NEAR(t.length(), p.length(), 1e-12);
    EXPECT_EQ(t.closed(), p.closed());
    ASSERT_EQ(t.elements().size(), p.elements().size());
    // Points map by the rigid motion, tangents rotate by yaw, curvature unchanged.
    for (double s = 0.0; s <= p.length(); s += p.length() / 37) {
      const fc::PathPoint a = p.at(s), b = t.at(s);
      EXPECT_NEAR((b.position - (R * a.position + offset)).norm(), 0.0, 1e-12) << s;
      EXPECT_NEAR(angleDiff(b.tangent, a.tangent + yaw), 0.0, 1e-9) << s;
      EXPECT_NEAR(b.curvature, a.curvature, 1e-12);
    }
    // Distances between sampled points are preserved.
    const std::vector<Vec2> sa = p.sample(0.043), sb = t.sample(0.043);
    ASSERT_EQ(sa.size(), sb.size());
    for (size_t i = 0; i < sa.size(); ++i)
      for (size_t j = i + 1; j < sa.size(); j += 3)
        EXPECT_NEAR((sa[i] - sa[j]).norm(), (sb[i] - sb[j]).norm(), 1e-12);
    // Projection commutes with the motion.
    for (int k = 0; k < 50; ++k) {
      const Vec2 q(u(rng), u(rng));
      const fc::PathProjection pa = p.project(q), pb = t.project(R * q + offset);
      EXPECT_NEAR(pb.s, pa.s, 1e-9);
      EXPECT_NEAR(pb.cross_track, pa.cross_track, 1e-12);
      EXPECT_NEAR(pb.distance, pa.distance, 1e-12);
    }
  }
}

// ---- angles -----------------------------------------------------------------------------------

TEST(Heading, WrapAngleRange) {
  EXPECT_DOUBLE_EQ(fc::wrapAngle(0.0), 0.0);
  EXPECT_DOUBLE_EQ(fc::wrapAngle(M_PI), M_PI);
  EXPECT_DOUBLE_EQ(fc::wrapAngle(-M_PI), M_PI);  // -pi is excluded
  EXPECT_NEAR(fc::wrapAngle(3 * M_PI), M_PI, 1e-12);
  EXPECT_NEAR(fc::wrapAngle(-3 * M_PI), M_PI, 1e-12);
  EXPECT_NEAR(fc::wrapAngle(0.5 + 10 * M_PI), 0.5, 1e-12);
  EXPECT_NEAR(fc::wrapAngle(-0.5 - 10 * M_PI), -0.5, 1e-12);
  EXPECT_NEAR(fc::wrapAngle(1.5 * M_PI), -0.5 * M_PI, 1e-12);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-100.0, 100.0);
  for (int i = 0; i < 10000; ++i) {
    const double a = u(rng), w = fc::wrapAngle(a);
    ASSERT_GT(w, -M_PI);
    ASSERT_LE(w, M_PI);
    const double k = (a - w) / (2 * M_PI);
    ASSERT_NEAR(k, std::round(k), 1e-9) << a;
  }
}

namespace {
double headingOf(const Eigen::Quaterniond& q) {
  const double c[4] = {q.x(), q.y(), q.z(), q.w()};
  return fc::headingFromQuaternion(c);
}
}  // namespace

TEST(Heading, FromQuaternionIsTheHeadAxisAzimuth) {
  using Eigen::AngleAxisd;
  using Eigen::Vector3d;
  // Head axis = body z. Ry(+90 deg) maps body z to world +x; Rz(azimuth) then turns it.
  for (double az_deg : {30.0, -150.0, 0.0, 90.0, 179.0, -45.0}) {
    const double az = units::degToRad(az_deg);
    for (double roll : {0.0, 0.4, 1.7, -2.9, M_PI}) {
      for (double elevation : {0.0, 0.3, -0.5}) {
        // Roll about the head axis itself (applied first, in the body frame), tilt up/down.
        const Eigen::Quaterniond q = AngleAxisd(az, Vector3d::UnitZ()) *
                                     AngleAxisd(M_PI / 2 - elevation, Vector3d::UnitY()) *
                                     AngleAxisd(roll, Vector3d::UnitZ());
        // The test's own check of the construction: body z is where we want it.
        const Vector3d axis = q * Vector3d::UnitZ();
        ASSERT_NEAR(axis.z(), std::sin(elevation), 1e-12);
        ASSERT_NEAR(std::atan2(axis.y(), axis.x()), fc::wrapAngle(az), 1e-12);
        EXPECT_NEAR(angleDiff(headingOf(q), az), 0.0, 1e-12)
            << "azimuth " << az_deg << " roll " << roll << " elevation " << elevation;
      }
    }
  }
  // The 30-degree example of the brief, and a heading that must not move with the roll.
  const Eigen::Quaterniond q30 =
      AngleAxisd(M_PI / 6, Vector3d::UnitZ()) * AngleAxisd(M_PI / 2, Vector3d::UnitY());
  EXPECT_NEAR(headingOf(q30), M_PI / 6, 1e-12);
  // Identity: the head axis points straight up; any roll about world x tilts it to azimuth -90.
  const Eigen::Quaterniond tilted(AngleAxisd(0.2, Vector3d::UnitX()));
  EXPECT_NEAR(headingOf(tilted), -M_PI / 2, 1e-12);
}

// ---- path descriptions ------------------------------------------------------------------------

TEST(PathSpec, Rectangle) {
  const fc::PathSpec s = fc::pathSpecFromYaml(
      YAML::Load("{shape: rectangle, width: 0.3, height: 0.2, turn: right, laps: 2}"));
  EXPECT_EQ(s.frame, fc::PathFrame::Start);
  EXPECT_EQ(s.laps, 2);
  EXPECT_TRUE(s.path.closed());
  ASSERT_EQ(s.path.elements().size(), 4u);
  EXPECT_NEAR(s.path.length(), 1.0, 1e-12);
  EXPECT_NEAR((s.path.elements()[1].start - Vec2(0.3, 0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((s.path.elements()[2].start - Vec2(0.3, -0.2)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(s.path.turnAfter(0), -M_PI / 2, 1e-12);
  EXPECT_NE(s.description.find("rectangle"), std::string::npos);
  EXPECT_NE(s.description.find("right"), std::string::npos);
  // Default turn: left.
  const fc::PathSpec l =
      fc::pathSpecFromYaml(YAML::Load("{shape: rectangle, width: 0.3, height: 0.3}"));
  EXPECT_NEAR(l.path.turnAfter(0), M_PI / 2, 1e-12);
  EXPECT_EQ(l.laps, 1);
}

TEST(PathSpec, TriangleCircleAndPolyline) {
  const fc::PathSpec t = fc::pathSpecFromYaml(YAML::Load("{shape: triangle, side: 0.3}"));
  EXPECT_NEAR(t.path.length(), 0.9, 1e-12);
  ASSERT_EQ(t.path.elements().size(), 3u);
  EXPECT_NEAR((t.path.elements()[2].start - Vec2(0.15, 0.3 * std::sqrt(3.0) / 2)).norm(), 0.0,
              1e-12);
  EXPECT_NEAR(t.path.turnAfter(1), 2 * M_PI / 3, 1e-12);

  const fc::PathSpec c =
      fc::pathSpecFromYaml(YAML::Load("shape: circle\nradius: 0.2\nturn: right\nframe: world\n"));
  EXPECT_EQ(c.frame, fc::PathFrame::World);
  EXPECT_TRUE(c.path.closed());
  EXPECT_NEAR(c.path.length(), 2 * M_PI * 0.2, 1e-12);
  EXPECT_NEAR(c.path.at(0).curvature, -5.0, 1e-12);
  EXPECT_NEAR(c.path.at(0).position.norm(), 0.0, 1e-12);
  EXPECT_NEAR(c.path.at(0).tangent, 0.0, 1e-12);  // every shape starts heading along +x

  const fc::PathSpec p = fc::pathSpecFromYaml(
      YAML::Load("{shape: polyline, points: [[0, 0], [0.2, 0], [0.35, 0.15], [0.5, 0]]}"));
  EXPECT_FALSE(p.path.closed());
  EXPECT_EQ(p.path.elements().size(), 3u);
  EXPECT_NEAR(p.path.length(), 0.2 + 2 * 0.15 * std::sqrt(2.0), 1e-12);
  const fc::PathSpec pc = fc::pathSpecFromYaml(YAML::Load(
      "{shape: polyline, closed: true, laps: 3, points: [[0, 0], [0.2, 0], [0.2, 0.1]]}"));
  EXPECT_TRUE(pc.path.closed());
  EXPECT_EQ(pc.laps, 3);
  EXPECT_NEAR(pc.path.length(), 0.2 + 0.1 + std::hypot(0.2, 0.1), 1e-12);
}

TEST(PathSpec, ErrorsNameTheField) {
  std::string e = specError("{shape: rectangle, width: 0.3, height: 0.3, colour: red}");
  EXPECT_NE(e.find("unknown field 'colour'"), std::string::npos) << e;
  e = specError("{shape: rectangle, width: -0.3, height: 0.3}");
  EXPECT_NE(e.find("'width'"), std::string::npos) << e;
  EXPECT_NE(e.find("out of range"), std::string::npos) << e;
  e = specError("{shape: rectangle, width: 0.3}");
  EXPECT_NE(e.find("'height'"), std::string::npos) << e;
  e = specError("{shape: circle, radius: 0}");
  EXPECT_NE(e.find("'radius'"), std::string::npos) << e;
  e = specError("{shape: triangle, side: abc}");
  EXPECT_NE(e.find("'side'"), std::string::npos) << e;
  e = specError("{shape: triangle, side: 0.3, turn: up}");
  EXPECT_NE(e.find("'turn'"), std::string::npos) << e;
  EXPECT_NE(e.find("up"), std::string::npos) << e;
  e = specError("{shape: polyline, points: [[0, 0], [1, 0]], laps: 2}");
  EXPECT_NE(e.find("'laps'"), std::string::npos) << e;
  EXPECT_NE(e.find("open"), std::string::npos) << e;
  e = specError("{shape: rectangle, width: 0.3, height: 0.3, laps: 0}");
  EXPECT_NE(e.find("'laps'"), std::string::npos) << e;
  e = specError("{shape: polyline}");
  EXPECT_NE(e.find("'points'"), std::string::npos) << e;
  e = specError("{shape: polyline, points: [[0, 0], [1]]}");
  EXPECT_NE(e.find("points[1]"), std::string::npos) << e;
  e = specError("{shape: polyline, points: [[0, 0], [0, 0]]}");
  EXPECT_NE(e.find("coincide"), std::string::npos) << e;
  e = specError("{shape: hexagon}");
  EXPECT_NE(e.find("unknown shape 'hexagon'"), std::string::npos) << e;
  e = specError("{width: 0.3}");
  EXPECT_NE(e.find("'shape'"), std::string::npos) << e;
  e = specError("{shape: circle, radius: 0.2, frame: robot}");
  EXPECT_NE(e.find("'frame'"), std::string::npos) << e;
  e = specError("[1, 2]");
  EXPECT_NE(e.find("map"), std::string::npos) << e;
  // Every message starts with the subject.
  EXPECT_EQ(e.rfind("path:", 0), 0u) << e;
}

// Values of the wrong kind had escaped as yaml-cpp's "bad conversion", naming no field.
TEST(PathSpec, ValuesOfTheWrongKindNameTheField) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"{shape: [circle], radius: 0.2}", "'shape' must be a single value"},
      {"{shape: circle, radius: 0.2, turn: {left: 1}}", "'turn' must be a single value"},
      {"{shape: circle, radius: 0.2, frame: [start]}", "'frame' must be a single value"},
      {"{shape: polyline, points: [[0, 0], [1, 0]], closed: maybe}",
       "'closed' must be true or false, got 'maybe'"},
      {"{shape: polyline, points: [[0, 0], [1, 0]], closed: [true]}",
       "'closed' must be a single value"},
      {"{shape: rectangle, width: 0.3, height: 0.3, laps: many}",
       "'laps' must be a whole number in [1, 100], got 'many'"},
      {"{shape: polyline, points: [[0, 0], [.nan, 1]]}", "points[1] must hold two finite numbers"},
      {"{[shape]: circle, radius: 0.2}", "the keys of 'path' must be plain names"},
  };
  for (const auto& [yaml, expected] : cases) {
    const std::string e = specError(yaml);
    EXPECT_NE(e.find(expected), std::string::npos) << yaml << " -> " << e;
    EXPECT_EQ(e.find("bad conversion"), std::string::npos) << yaml << " -> " << e;
  }
  // A long unknown value is quoted cut.
  const std::string e = specError("{shape: " + std::string(5000, 'k') + "}");
  EXPECT_LT(e.size(), 300u) << e.size();
}
