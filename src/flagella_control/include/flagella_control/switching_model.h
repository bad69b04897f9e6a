// The calibrated kinematic model of the binary input used for the tracking bound
// (docs/model.md 7.5): after every switch of sign the head stands still (no motion, no yaw) for a
// dead time, then moves with the steady response of the new sign (SignResponse: yaw rate and
// body velocity, so a held sign draws the calibrated circle). The dead time is the one that makes
// periodic switching reproduce the measured advance per period; the measured heading drift per
// period is spread evenly over time. Allocation-free.
#pragma once

#include "flagella_control/calibration.h"
#include "flagella_control/path.h"

namespace flagella::control {

/// Where one stretch of the model leaves the robot.
struct ModelMotion {
  Vec2 displacement = Vec2::Zero();  ///< world frame [m]
  double turn = 0.0;                 ///< heading change [rad]
  double dead_remaining = 0.0;       ///< dead time still to run at its end [s]
};

class DeadTimeModel {
 public:
  /// Throws std::invalid_argument (via BinaryCalibration::validate) for an unusable calibration.
  explicit DeadTimeModel(const BinaryCalibration& calibration);
  /// Fitted dead time after a switch [s], in [0, T/2].
  double deadTime() const { return dead_time_; }
  /// Advance per period of the model with the fitted dead time [m] (the measured one unless even
  /// a zero dead time cannot reach it).
  double modelAdvance() const { return model_advance_; }
  /// Measured minus modelled direction of the advance per period [rad].
  double directionMismatch() const { return direction_mismatch_; }
  double switchPeriod() const { return period_; }
  /// Yaw rate of a sign [rad/s].
  double yawRate(int sign) const { return sign > 0 ? plus_.yaw_rate : minus_.yaw_rate; }
  double driftPerPeriod() const { return drift_per_period_; }
  /// The model with the yaw rates and the sideways body velocities scaled by `factor` (as an
  /// error in the lateral force does: the velocity along the head axis stays) and the dead time
  /// fitted again to the same advance per period. Allocation-free.
  DeadTimeModel scaled(double factor) const;

  /// Motion over the first t seconds of a period (0 <= t <= T) that holds +omega for
  /// `plus_duration`, then -omega, begun at `heading` after `previous_sign` (0: stopped, which
  /// counts as a switch) with `dead_remaining` seconds of an earlier dead time still to run.
  ModelMotion until(double heading, int previous_sign, double dead_remaining, double plus_duration,
                    double t) const;

 private:
  DeadTimeModel() = default;
  void fit(double advance_per_period, double advance_angle);
  ModelMotion segment(int sign, double heading, double dead, double duration) const;
  ModelMotion until(double heading, int previous_sign, double dead_remaining, double plus_duration,
                    double t, double dead_time) const;

  SignResponse plus_, minus_;
  double period_ = 0.0, drift_per_period_ = 0.0;
  double advance_per_period_ = 0.0, advance_angle_ = 0.0;
  double dead_time_ = 0.0, model_advance_ = 0.0, direction_mismatch_ = 0.0;
};

}  // namespace flagella::control
