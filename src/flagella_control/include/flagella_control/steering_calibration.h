// What the mass-transformer controller knows of the helical robot (docs/model.md 7.4), estimated
// from the simulator by flagella_steer_calibrate and stored as YAML: the buckling threshold, the
// cruise, what one buckle pulse does to the direction of travel, and how the slider pitches the
// head.
//
// Buckle cycle model: a cycle turns the mean direction of travel f by a small rotation, written as
// its components (up, left) in the plane normal to f: u, the world's up projected on that plane,
// and w = u x f (the left side when f is horizontal). It is a constant part (bias_up, bias_left)
// plus a part of size `deflection` toward the angle chi from u toward w,
//   chi = roll_sign * roll + shaft_sign * shaft + phase_offset,
// with `roll` the head's roll angle (its m1 axis from u toward w, from the IMU) and `shaft` the
// motor's shaft angle relative to the head (the integral of the commanded rate) at the start of
// the cycle: the flagellum buckles toward a direction fixed by its own phase.
#pragma once

#include <string>

namespace flagella::control {

enum class BuckleScheduleKind {
  Relax,      ///< omega_2 for the pulse, then omega_1 until the helix has relaxed, then cruise
  ThreeLevel  ///< omega_1 << omega_b, then omega_2 >> omega_b, then omega_3 < omega_b
};

const char* scheduleName(BuckleScheduleKind kind);
/// "relax" or "three_level"; std::invalid_argument otherwise.
BuckleScheduleKind scheduleFromName(const std::string& name);

/// One buckle schedule's motor levels, durations and measured effect.
struct BuckleSchedule {
  BuckleScheduleKind kind = BuckleScheduleKind::Relax;
  double lead_omega = 0.0;                   ///< omega_1 before the pulse (three_level) [rad/s]
  double lead_duration = 0.0;                ///< [s] (0 for relax)
  double pulse_omega = 0.0;                  ///< omega_2 > omega_b [rad/s]
  double pulse_duration = 0.0;               ///< [s]
  double relax_omega = 0.0;                  ///< omega_1 after the pulse (relax) [rad/s]
  double relax_duration = 0.0;               ///< [s] (0 for three_level)
  double bias_up = 0.0, bias_left = 0.0;     ///< constant turn per cycle [rad]
  double deflection = 0.0;                   ///< size of the phase-dependent turn per cycle [rad]
  double roll_sign = 1.0, shaft_sign = 1.0;  ///< +-1
  double phase_offset = 0.0;                 ///< [rad], (-pi, pi]
  double phase_spread = 0.0;  ///< RMS residual of the turn in the calibration runs [rad]
  /// Turn per metre of slider offset from park held through the cycle, (up, left) [rad/m]: a
  /// buckling flagellum turns the robot by the slider's small couple many times more than the
  /// couple pitches it cruising (optional in a file: 0 when absent).
  double up_per_slider = 0.0, left_per_slider = 0.0;

  double cycleDuration() const { return lead_duration + pulse_duration + relax_duration; }
  /// Motor rate at time `s` since the cycle started (cruise after the cycle).
  double omegaAt(double s, double cruise_omega) const;
  /// Direction chi of the phase-dependent part for a cycle started at this roll and shaft [rad].
  double direction(double roll, double shaft) const;
  /// The turn (up, left) [rad] of a cycle whose phase-dependent part points toward `chi`.
  void turnToward(double chi, double& up, double& left) const;
  /// The turn (up, left) [rad] of a cycle started at this roll and shaft angle.
  void predictedTurn(double roll, double shaft, double& up, double& left) const {
    turnToward(direction(roll, shaft), up, left);
  }
  /// The largest turn along the unit direction (up, left) of the plane normal to travel one
  /// cycle can give [rad]; <= 0 when buckling cannot turn that way.
  double bestTurn(double up, double left) const {
    return bias_up * up + bias_left * left + deflection;
  }
};

struct SteeringCalibration {
  double buckling_threshold = 0.0;  ///< omega_b [rad/s]
  double cruise_omega = 0.0;        ///< omega_3 < omega_b [rad/s]
  double cruise_speed = 0.0;        ///< net speed along the head axis at cruise [m/s]
  BuckleSchedule relax, three_level;
  /// Pitch rate of the direction of travel per metre of slider travel from the park position,
  /// with the head horizontal [rad/s per m] (positive: moving the slider toward +t^0, to the
  /// tails, raises the nose).
  double pitch_rate_per_slider = 0.0;
  /// Crab angle per metre of slider travel from the park position, cruising level: the course
  /// over ground minus the head axis's azimuth (positive: course left of the axis) [rad/m].
  /// Micrometres of COM-COV offset turn the course by degrees (docs/model.md 7.4).
  double crab_per_slider = 0.0;
  double park_position = 0.0;  ///< slider position with no COM-COV couple (nominal l_0) [m]
  /// Nose-up pitch rate of the head axis cruising with the slider at park [rad/s]: the robot's
  /// own pitching, so that its cruise pitches not at all (its pitch neutral) at park minus this
  /// over pitch_rate_per_slider. Optional in a file (0 when absent).
  double park_pitch_rate = 0.0;
  double slider_min = 0.0, slider_max = 0.0;  ///< travel [m]
  std::string source;

  const BuckleSchedule& schedule(BuckleScheduleKind kind) const {
    return kind == BuckleScheduleKind::Relax ? relax : three_level;
  }
  /// Throws std::invalid_argument naming the field and its allowed range.
  void validate() const;
};

/// Reads a steering calibration (format of saveSteeringCalibration). Throws std::runtime_error
/// naming the file and the field.
SteeringCalibration loadSteeringCalibration(const std::string& path);
void saveSteeringCalibration(const SteeringCalibration& calibration, const std::string& path);

}  // namespace flagella::control
