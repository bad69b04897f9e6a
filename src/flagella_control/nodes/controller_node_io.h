// What the controller nodes share: private parameters with defaults, the IMU message as a
// controller core's inputs, and the status period from ~status_rate.
#pragma once

#include <ros/ros.h>
#include <sensor_msgs/Imu.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "flagella_control/controller_core.h"
#include "flagella_control/pending_fix.h"

namespace flagella::control::node {

template <typename T>
T param(ros::NodeHandle& pnh, const std::string& name, T fallback) {
  T value = fallback;
  pnh.param(name, value, fallback);
  return value;
}

/// 1 / ~status_rate [s]; throws std::invalid_argument outside (0, 1000] Hz.
inline double statusPeriod(ros::NodeHandle& pnh) {
  const double rate = param(pnh, "status_rate", 5.0);
  if (!(rate > 0.0 && rate <= 1000.0))
    throw std::invalid_argument("~status_rate must be in (0, 1000] Hz, got " +
                                std::to_string(rate));
  return 1.0 / rate;
}

/// Time, orientation, rates and specific force of an IMU sample into `in` (position untouched).
/// The sample is valid when its orientation and specific force are finite and its orientation
/// covariance does not say "no orientation" (-1, REP-145).
inline void imuToInputs(const sensor_msgs::Imu& msg, ControllerInputs& in) {
  const auto& q = msg.orientation;
  const auto& w = msg.angular_velocity;
  const auto& a = msg.linear_acceleration;
  in.time = msg.header.stamp.toSec();
  in.imu_valid = std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z) &&
                 std::isfinite(q.w) && std::isfinite(a.x) && std::isfinite(a.y) &&
                 std::isfinite(a.z) && msg.orientation_covariance[0] >= 0.0;
  const double values[] = {q.x, q.y, q.z, q.w, w.x, w.y, w.z, a.x, a.y, a.z};
  for (int k = 0; k < 4; ++k) in.orientation[k] = values[k];
  for (int k = 0; k < 3; ++k) in.angular_velocity[k] = values[4 + k];
  for (int k = 0; k < 3; ++k) in.linear_acceleration[k] = values[7 + k];
}

}  // namespace flagella::control::node
