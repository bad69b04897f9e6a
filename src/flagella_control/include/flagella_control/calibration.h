// The robot's response to its single binary input (docs/model.md 7.3), as the planner and the
// path-following controller use it: steady motion at constant +omega and -omega, and the net
// motion of periodic switching. Estimated from the simulator (or measured data) by
// flagella_calibrate and stored as YAML.
#pragma once

#include <string>

namespace flagella::control {

/// Steady motion at one constant motor sign, in the horizontal plane of the output frame (z up).
/// Heading psi is the azimuth of the head axis (IMU body z) projected on the horizontal plane.
struct SignResponse {
  double yaw_rate = 0.0;         ///< d psi/dt, signed, counter-clockwise positive [rad/s]
  double circle_radius = 0.0;    ///< least-squares circle through the head-centre path [m]
  double axis_path_angle = 0.0;  ///< path tangent minus head-axis azimuth, in (-pi, pi] [rad]
  double speed = 0.0;            ///< head-centre path speed [m/s]
  /// Head-centre velocity in the heading frame: [0] along the head axis, [1] to its left [m/s].
  double body_velocity[2] = {0.0, 0.0};
};

struct BinaryCalibration {
  double omega = 0.0;          ///< |motor rate| of the binary input [rad/s]
  double switch_period = 0.0;  ///< T of the periodic-switching run: +omega T/2, then -omega T/2 [s]
  SignResponse plus, minus;    ///< constant +omega, constant -omega
  /// Periodic switching, one period starting with the + half:
  double advance_per_period = 0.0;  ///< net head-centre displacement [m]
  /// Direction of that displacement relative to the heading at the start of the period [rad].
  double advance_angle = 0.0;
  double heading_drift_per_period = 0.0;  ///< net heading change [rad]
  std::string source;                     ///< how it was obtained (config, durations)

  /// Net advance speed under periodic switching [m/s].
  double advanceSpeed() const { return advance_per_period / switch_period; }
  /// Mean yaw rate of a period with a fraction `duty` of it at +omega (0..1).
  double meanYawRate(double duty) const {
    return duty * plus.yaw_rate + (1.0 - duty) * minus.yaw_rate;
  }
  /// Throws std::invalid_argument naming the field when a value is unusable (non-finite,
  /// omega/period/advance not positive, yaw rates of equal sign or zero).
  void validate() const;
};

/// Reads a calibration YAML (format written by saveCalibration). Throws std::runtime_error
/// with the file name and the offending field.
BinaryCalibration loadCalibration(const std::string& path);
void saveCalibration(const BinaryCalibration& calibration, const std::string& path);

}  // namespace flagella::control
