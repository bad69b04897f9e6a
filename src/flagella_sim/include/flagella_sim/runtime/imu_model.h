// A strapdown IMU fixed to the rigid head, in the head frame (m1^0, m2^0, t^0): orientation,
// angular rate and specific force (REP-145: an IMU at rest reads +g upward), with white noise
// and constant biases.
#pragma once

#include <Eigen/Geometry>
#include <random>
#include <string>

#include "flagella_sim/core/types.h"

namespace flagella {

struct ImuOptions {
  double rate = 100.0;                 ///< samples per second of simulated time [Hz]
  double orientation_noise_std = 0.0;  ///< per axis, small-angle [rad]
  double gyro_noise_std = 0.0;         ///< per axis [rad/s]
  double accel_noise_std = 0.0;        ///< per axis [m/s^2]
  Vec3 gyro_bias = Vec3::Zero();       ///< [rad/s], head frame
  Vec3 accel_bias = Vec3::Zero();      ///< [m/s^2], head frame
  unsigned seed = 1;

  /// Throws ConfigError naming the field and its range if a value is unusable.
  void validate() const;
};

/// The true motion of the head at one instant, in the world frame.
struct HeadMotion {
  double time = 0.0;
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  ///< head frame in world
  Vec3 angular_velocity = Vec3::Zero();                             ///< world frame [rad/s]
  Vec3 acceleration = Vec3::Zero();                                 ///< of x_1 [m/s^2]
};

struct ImuSample {
  double time = 0.0;
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  ///< head frame in world
  Vec3 angular_velocity = Vec3::Zero();                             ///< head frame [rad/s]
  Vec3 linear_acceleration = Vec3::Zero();  ///< specific force, head frame [m/s^2]
  /// Diagonal variances (REP-145); 0 means "not known" in sensor_msgs/Imu.
  double orientation_variance = 0.0;
  double angular_velocity_variance = 0.0;
  double linear_acceleration_variance = 0.0;
};

/// The specific force a - g of the head's motion in the head frame [m/s^2] (reads +|g| upward at
/// rest).
Vec3 specificForceInHead(const HeadMotion& truth, const Vec3& gravity);

class ImuModel {
 public:
  ImuModel(ImuOptions options, Vec3 gravity);
  /// Measures the given true motion: rotates into the head frame, adds bias and noise.
  ImuSample measure(const HeadMotion& truth);
  const ImuOptions& options() const { return options_; }

 private:
  Vec3 noise(double std_dev);

  ImuOptions options_;
  Vec3 gravity_;
  std::mt19937 rng_;
  std::normal_distribution<double> unit_normal_{0.0, 1.0};
};

/// Finite-difference estimator of the head's angular velocity and acceleration from successive
/// poses (first order; exact for a constant rotation rate over the interval).
class HeadMotionTracker {
 public:
  /// Records the head pose and centre velocity at `time`.
  void update(double time, const Eigen::Quaterniond& orientation, const Vec3& velocity);
  /// The motion at the latest update (zero rates until two updates have been seen).
  HeadMotion motion() const { return latest_; }
  void clear() { have_previous_ = false, latest_ = HeadMotion{}; }

 private:
  bool have_previous_ = false;
  double time_ = 0.0;
  Eigen::Quaterniond orientation_ = Eigen::Quaterniond::Identity();
  Vec3 velocity_ = Vec3::Zero();
  HeadMotion latest_;
};

}  // namespace flagella
