// The path-following controller node: a thin ROS shell around a controller core
// (RecedingHorizonController, PathFollowingController or ScheduleController, built by
// path_controller_factory.h from the ~mode and gain parameters). It steps the core on every IMU
// sample with the latest camera fix (used once), publishes the motor command stamped with the
// IMU stamp, the controller status and the anchored reference path. Time is the IMU stamp only.
#pragma once

#include <geometry_msgs/PointStamped.h>
#include <nav_msgs/Path.h>
#include <ros/ros.h>
#include <sensor_msgs/Imu.h>

#include <memory>
#include <string>

#include "controller_node_io.h"
#include "flagella_control/path_controller_factory.h"

namespace flagella::control::node {

class PathFollowerNode {
 public:
  /// Reads parameters; throws std::runtime_error / std::invalid_argument on bad input.
  PathFollowerNode(ros::NodeHandle& nh, ros::NodeHandle& private_nh);
  /// 0, or 1 when the start-up watchdog ended the node (no IMU sample).
  int exitCode() const { return watchdog_->exitCode(); }

 private:
  void onImu(const sensor_msgs::Imu& msg);
  void onCameraFix(const geometry_msgs::PointStamped& msg);
  void onPath(const nav_msgs::Path& msg);
  void build(flagella::control::PathSpec spec);
  void publishStatus(const ros::Time& stamp, const flagella::control::ControllerOutputs& out);
  void publishReference(const ros::Time& stamp);

  std::string world_frame_;
  flagella::control::BinaryCalibration calibration_;
  flagella::control::PathControllerOptions controller_options_;  ///< mode and gains
  std::unique_ptr<flagella::control::PathControllerBase> controller_;
  flagella::control::ControllerInputs inputs_;
  PendingFix fix_;
  bool reference_published_ = false;
  bool exit_when_finished_ = false;
  double status_period_ = 0.2;
  double last_status_time_ = -1e9;
  flagella::control::ControllerMode last_mode_ = flagella::control::ControllerMode::Idle;
  double finished_at_ = -1.0;
  double linger_ = 1.0;

  ros::Publisher motor_pub_, status_pub_, reference_pub_;
  std::unique_ptr<StartupWatchdog> watchdog_;
  ros::Subscriber imu_sub_, fix_sub_, path_sub_;
};

}  // namespace flagella::control::node
