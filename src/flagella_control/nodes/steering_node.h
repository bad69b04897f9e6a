// The mass-transformer steering node: a thin ROS shell around MassTransformerController
// (docs/model.md 7.4). It steps the core on every IMU sample (orientation and the head
// accelerometer in linear_acceleration) with the latest 3-D camera fix (used once), and publishes
// the slider command, then the motor command stamped with the IMU stamp (lockstep answer), the
// controller status, the waypoints and the slider as rviz markers, and the estimated path.
#pragma once

#include <geometry_msgs/PointStamped.h>
#include <nav_msgs/Path.h>
#include <ros/ros.h>
#include <sensor_msgs/Imu.h>

#include <memory>
#include <string>

#include "controller_node_io.h"
#include "flagella_control/mass_transformer_controller.h"

namespace flagella::control::node {

class SteeringNode {
 public:
  /// Reads parameters; throws std::runtime_error / std::invalid_argument on bad input.
  SteeringNode(ros::NodeHandle& nh, ros::NodeHandle& private_nh);
  /// 0, or 1 when the start-up watchdog ended the node (no IMU sample).
  int exitCode() const { return watchdog_->exitCode(); }

 private:
  void onImu(const sensor_msgs::Imu& msg);
  void onCameraFix(const geometry_msgs::PointStamped& msg);
  void publishStatus(const ros::Time& stamp, const ControllerOutputs& out);
  void publishWaypoints(const ros::Time& stamp);
  void publishSlider(const ros::Time& stamp, double position);
  void publishEstimate(const ros::Time& stamp);

  std::string world_frame_, head_frame_;
  std::unique_ptr<MassTransformerController> controller_;
  ControllerInputs inputs_;
  PendingFix fix_;
  bool waypoints_published_ = false;
  bool exit_when_finished_ = false;
  double status_period_ = 0.2, estimate_period_ = 0.5;
  double last_status_time_ = -1e9, last_estimate_time_ = -1e9;
  SteeringMode last_mode_ = SteeringMode::Waiting;
  double finished_at_ = -1.0;
  double linger_ = 1.0;
  nav_msgs::Path estimated_path_;

  ros::Publisher motor_pub_, slider_pub_, status_pub_, waypoint_pub_, slider_marker_pub_,
      estimate_pub_;
  std::unique_ptr<StartupWatchdog> watchdog_;
  ros::Subscriber imu_sub_, fix_sub_;
};

}  // namespace flagella::control::node
