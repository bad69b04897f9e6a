#include "flagella_control/heading.h"

#include <cmath>

namespace flagella::control {

double headingFromQuaternion(const double q[4]) {
  const double x = q[0], y = q[1], z = q[2], w = q[3];
  // Third column of the rotation matrix of a unit quaternion: R e_z.
  const double ax = 2.0 * (x * z + w * y);
  const double ay = 2.0 * (y * z - w * x);
  return std::atan2(ay, ax);
}

double wrapAngle(double angle) {
  const double two_pi = 2.0 * M_PI;
  double a = std::fmod(angle + M_PI, two_pi);
  if (a <= 0.0) a += two_pi;
  return a - M_PI;
}

}  // namespace flagella::control
