#include "flagella_control/head_attitude.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

namespace flagella::control {

NormalPlane normalPlane(const Vec3& f) {
  NormalPlane p;
  Vec3 u = Vec3::UnitZ() - f.z() * f;
  if (u.norm() < 1e-3) u = Vec3::UnitX() - f.x() * f;
  p.u = u.normalized();
  p.w = p.u.cross(f);
  return p;
}

HeadAttitude attitudeFromQuaternion(const double q[4]) {
  const Eigen::Quaterniond quaternion(q[3], q[0], q[1], q[2]);
  const Eigen::Matrix3d R = quaternion.normalized().toRotationMatrix();
  HeadAttitude a;
  a.forward = -R.col(2);
  const NormalPlane plane = normalPlane(a.forward);
  const Vec3 m1 = R.col(0);
  a.roll = std::atan2(m1.dot(plane.w), m1.dot(plane.u));
  return a;
}

double azimuthOf(const Vec3& f) { return std::atan2(f.y(), f.x()); }

double elevationOf(const Vec3& f) { return std::asin(std::clamp(f.z() / f.norm(), -1.0, 1.0)); }

Vec3 directionFrom(double azimuth, double elevation) {
  return Vec3(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth),
              std::sin(elevation));
}

double travelElevationFromAcceleration(const double a[3], double min_norm) {
  const double norm = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
  if (!(norm >= min_norm)) return std::numeric_limits<double>::quiet_NaN();
  return -std::asin(std::clamp(a[2] / norm, -1.0, 1.0));
}

}  // namespace flagella::control
