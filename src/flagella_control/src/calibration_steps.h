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
/// and the applied rate (after the soft start) times dt to `shaft`.
template <class Rate>
void advance(SessionDriver& driver, double seconds, const Rate& omega, Vec3& sum, double& shaft) {
  const long steps = std::lround(seconds / driver.dt());
  for (long k = 0; k < steps; ++k) {
    // The shaft angle of the rate applied (the soft start included): the controller's phase
    // law is in the angle its own commands give, which the simulator applies as they are.
    shaft += driver.step(omega(k * driver.dt())) * driver.dt();
    sum += attitudeOf(driver).forward;
  }
}

/// The least-squares slope of y against t, accumulated sample by sample (two distinct t at least).
struct SlopeFit {
  double n = 0, st = 0, sy = 0, stt = 0, sty = 0;
  void add(double t, double y) { n += 1, st += t, sy += y, stt += t * t, sty += t * y; }
  double slope() const { return (n * sty - st * sy) / (n * stt - st * st); }
};

/// Steps `seconds` at the constant rate `omega` and returns the least-squares slope of the
/// elevation of the head's forward direction over them [rad/s].
inline double elevationRateOver(SessionDriver& driver, double seconds, double omega) {
  SlopeFit fit;
  const long steps = std::lround(seconds / driver.dt());
  for (long k = 1; k <= steps; ++k) {
    driver.step(omega);
    fit.add(k * driver.dt(), elevationOf(attitudeOf(driver).forward));
  }
  return fit.slope();
}

}  // namespace flagella::control::calibration_steps
