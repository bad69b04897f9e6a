// Heading of the robot in the horizontal plane of the output frame (z up): the azimuth of the
// head axis (docs/model.md 7.1: psi is the azimuth of the projection of ahat, the IMU body z).
#pragma once

namespace flagella::control {

/// Azimuth atan2(a_y, a_x) of the head axis a = R(q) e_z, from a quaternion x, y, z, w.
double headingFromQuaternion(const double q[4]);

/// Wraps an angle to (-pi, pi].
double wrapAngle(double angle);

}  // namespace flagella::control
