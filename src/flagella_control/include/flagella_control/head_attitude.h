// The helical robot's attitude as its controller sees it (output frame, z up; docs/model.md 7.4):
// the direction of travel f = -t^0 (the robot swims head first), its azimuth and elevation, the
// head's roll about it, and the elevation from a gravity-dominated accelerometer reading.
#pragma once

#include <Eigen/Core>

namespace flagella::control {

using Vec3 = Eigen::Vector3d;

/// Basis of the plane normal to a direction f: u, the world's up projected on the plane
/// (normalised), and w = u x f (the left side when f is horizontal). For f within about 0.06 deg
/// of vertical, u is the world x axis projected instead.
struct NormalPlane {
  Vec3 u = Vec3::UnitZ(), w = Vec3::UnitY();
};
NormalPlane normalPlane(const Vec3& forward);

struct HeadAttitude {
  Vec3 forward = Vec3::UnitX();  ///< -t^0, unit
  double roll = 0.0;             ///< angle of the head's m1 axis from u toward w [rad]
};

/// From an IMU quaternion x, y, z, w (head frame (m1, m2, t) in the world).
HeadAttitude attitudeFromQuaternion(const double q[4]);

/// Azimuth atan2(f_y, f_x) and elevation asin(f_z) of a direction [rad].
double azimuthOf(const Vec3& f);
double elevationOf(const Vec3& f);
/// Unit direction at an azimuth and elevation.
Vec3 directionFrom(double azimuth, double elevation);

/// Elevation of the direction of travel -t^0 from a specific-force reading in the head frame
/// (at rest the accelerometer reads +g upward, so a_z = g sin(elevation of t^0)): -asin(a_z/|a|).
/// NaN when |a| is below `min_norm` (free fall or no reading).
double travelElevationFromAcceleration(const double a[3], double min_norm);

}  // namespace flagella::control
