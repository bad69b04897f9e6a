#include "flagella_sim/core/geometry.h"

#include <cmath>

namespace flagella {

namespace {
// Below this |a x b| the two tangents are treated as parallel (transport is the identity).
constexpr double kParallelTolerance = 1e-14;
}  // namespace

Mat3 skew(const Vec3& a) {
  Mat3 m;
  m << 0.0, -a.z(), a.y(), a.z(), 0.0, -a.x(), -a.y(), a.x(), 0.0;
  return m;
}

Vec3 parallelTransport(const Vec3& u, const Vec3& a, const Vec3& b) {
  // docs/model.md 1.3: the rotation about a x b taking a to b, in Rodrigues' form without
  // trigonometry: P(u) = c u + (a x b) x u + ((a x b).u / (1 + c)) (a x b), c = a.b
  const Vec3 axis = a.cross(b);
  const double c = a.dot(b);
  if (axis.squaredNorm() < kParallelTolerance * kParallelTolerance) return u;
  return c * u + axis.cross(u) + (axis.dot(u) / (1.0 + c)) * axis;
}

double angleBetween(const Vec3& u, const Vec3& v) {
  return std::atan2(u.cross(v).norm(), u.dot(v));
}

double angleAbout(const Vec3& u, const Vec3& v, const Vec3& n) {
  return std::atan2(n.dot(u.cross(v)), u.dot(v));
}

Vec3 anyPerpendicular(const Vec3& t) {
  const Vec3 trial = std::abs(t.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  return (trial - trial.dot(t) * t).normalized();
}

}  // namespace flagella
