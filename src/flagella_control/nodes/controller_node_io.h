// What the controller nodes share: private parameters with defaults, file parameters relative to
// the launch directory, the IMU message as a controller core's inputs, the status period from
// ~status_rate, and the start-up watchdog.
#pragma once

#include <ros/ros.h>
#include <sensor_msgs/Imu.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "flagella_control/controller_core.h"
#include "flagella_control/pending_fix.h"
#include "flagella_sim/core/file_paths.h"

namespace flagella::control::node {

template <typename T>
T param(ros::NodeHandle& pnh, const std::string& name, T fallback) {
  T value = fallback;
  pnh.param(name, value, fallback);
  return value;
}

/// A file parameter (empty when unset); a relative path is taken against ~base_directory, which
/// the launch files set to the directory roslaunch was started in.
inline std::string fileParam(ros::NodeHandle& pnh, const std::string& name) {
  return flagella::resolveAgainst(param<std::string>(pnh, name, ""),
                                  param<std::string>(pnh, "base_directory", ""));
}

/// Ends the node when no IMU sample has arrived within ~startup_timeout wall seconds (default 60,
/// 0 = wait forever): a session whose simulator never started fails instead of waiting forever.
class StartupWatchdog {
 public:
  StartupWatchdog(ros::NodeHandle& nh, ros::NodeHandle& pnh, const std::string& imu_topic) {
    const double timeout = param(pnh, "startup_timeout", 60.0);
    if (!(timeout >= 0.0 && timeout <= 86400.0))
      throw std::invalid_argument(
          "~startup_timeout must be in [0, 86400] wall s (0: no limit), got " +
          std::to_string(timeout));
    if (timeout == 0.0) return;
    timer_ = nh.createWallTimer(
        ros::WallDuration(timeout),
        [this, imu_topic, timeout](const ros::WallTimerEvent&) {
          if (heard_) return;
          ROS_FATAL(
              "no IMU sample on %s within %.0f wall s of start: is the simulator running? "
              "(~startup_timeout)",
              imu_topic.c_str(), timeout);
          expired_ = true;
          ros::shutdown();
        },
        /*oneshot=*/true);
  }
  void heard() { heard_ = true; }
  /// The node's exit code: 1 when the watchdog ended it, else 0.
  int exitCode() const { return expired_ ? 1 : 0; }

 private:
  ros::WallTimer timer_;
  bool heard_ = false;
  bool expired_ = false;
};

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
