#include "flagella_sim/core/geometry.h"

#include <cmath>

namespace flagella {

Mat3 skew(const Vec3& a) {
  Mat3 m;
  m << 0.0, -a.z(), a.y(), a.z(), 0.0, -a.x(), -a.y(), a.x(), 0.0;
  return m;
}

double angleBetween(const Vec3& u, const Vec3& v) {
  return std::atan2(u.cross(v).norm(), u.dot(v));
}

Vec3 anyPerpendicular(const Vec3& t) {
  const Vec3 trial = std::abs(t.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  return (trial - trial.dot(t) * t).normalized();
}

}  // namespace flagella
