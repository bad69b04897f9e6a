// Steps of the steering calibration runs shared by the calibration and its response tables
// (private to the calibration library): the head's attitude and position in a session, and a run
// of steps at a motor rate that sums the direction of travel and integrates the shaft angle.
#pragma once

#include <cmath>

#include "flagella_control/head_attitude.h"
#include "flagella_control/session_driver.h"

namespace flagella::control::calibration_steps {

inline HeadAttitude attitudeOf(const SessionDriver& driver) {
  const Eigen::Quaterniond& q = driver.session().snapshot().head_orientation;
  const double quaternion[4] = {q.x(), q.y(), q.z(), q.w()};
  return attitudeFromQuaternion(quaternion);
}

inline Vec3 headPosition(const SessionDriver& driver) {
  return driver.session().snapshot().head_position;
}

/// Steps `seconds` at `omega(s)` (s from now), adding every step's forward direction to `sum`
/// and the commanded rate times dt to `shaft`.
template <class Rate>
void advance(SessionDriver& driver, double seconds, const Rate& omega, Vec3& sum, double& shaft) {
  const long steps = std::lround(seconds / driver.dt());
  for (long k = 0; k < steps; ++k) {
    const double rate = omega(k * driver.dt());
    driver.step(rate);
    shaft += rate * driver.dt();
    sum += attitudeOf(driver).forward;
  }
}

}  // namespace flagella::control::calibration_steps
