#include "path_follower_node.h"

#include <flagella_msgs/ControllerStatus.h>
#include <flagella_msgs/MotorCommand.h>

#include <cmath>
#include <stdexcept>

namespace flagella::control::node {

using flagella::control::ControllerMode;
using flagella::control::ControllerOutputs;

namespace {

constexpr int kQueue = 1000;
constexpr double kReferenceSpacing = 0.005;  // [m] between published reference poses

std::uint8_t toStatusMode(ControllerMode mode) {
  switch (mode) {
    case ControllerMode::Running:
      return flagella_msgs::ControllerStatus::RUNNING;
    case ControllerMode::Finished:
      return flagella_msgs::ControllerStatus::FINISHED;
    case ControllerMode::Fault:
      return flagella_msgs::ControllerStatus::FAULT;
    default:
      return flagella_msgs::ControllerStatus::IDLE;
  }
}

}  // namespace

PathFollowerNode::PathFollowerNode(ros::NodeHandle& nh, ros::NodeHandle& pnh) {
  controller_options_.mode = param<std::string>(pnh, "mode", controller_options_.mode);
  flagella::control::requirePathControllerMode(controller_options_.mode, "~mode");
  world_frame_ = param<std::string>(pnh, "world_frame", "world");
  const std::string calibration_file = fileParam(pnh, "calibration");
  if (calibration_file.empty())
    throw std::invalid_argument("~calibration (a YAML file) is required");
  calibration_ = flagella::control::loadCalibration(calibration_file);
  flagella::control::PathFollowingGains& gains = controller_options_.gains;
  gains.lookahead = param(pnh, "lookahead", gains.lookahead);
  gains.cross_track_integral = param(pnh, "cross_track_integral", gains.cross_track_integral);
  gains.heading_gain = param(pnh, "heading_gain", gains.heading_gain);
  gains.fix_gain = param(pnh, "fix_gain", gains.fix_gain);
  gains.min_pulse = param(pnh, "min_pulse", gains.min_pulse);
  gains.search_window = param(pnh, "search_window", gains.search_window);
  gains.imu_timeout = param(pnh, "imu_timeout", gains.imu_timeout);
  gains.fix_timeout = param(pnh, "fix_timeout", gains.fix_timeout);
  gains.sensor_fault_timeout = param(pnh, "sensor_fault_timeout", gains.sensor_fault_timeout);
  gains.finish_tolerance = param(pnh, "finish_tolerance", gains.finish_tolerance);
  gains.validate();
  flagella::control::RecedingHorizonGains& horizon = controller_options_.horizon_gains;
  horizon.horizon = param(pnh, "horizon", horizon.horizon);
  horizon.fallback_distance = param(pnh, "fallback_distance", horizon.fallback_distance);
  horizon.adapt = param(pnh, "adapt", horizon.adapt);
  horizon.validate();
  status_period_ = statusPeriod(pnh);
  exit_when_finished_ = param(pnh, "exit_when_finished", false);
  linger_ = param(pnh, "linger", 1.0);

  // The controller first (the receding-horizon one plans for seconds): a lockstep simulator
  // starts once motor_command has a publisher, and the IMU sample it then sends must be heard.
  const std::string path_file = fileParam(pnh, "path");
  if (!path_file.empty()) build(flagella::control::loadPathSpec(path_file));
  motor_pub_ = nh.advertise<flagella_msgs::MotorCommand>("motor_command", kQueue);
  status_pub_ = nh.advertise<flagella_msgs::ControllerStatus>("controller_status", kQueue);
  reference_pub_ = nh.advertise<nav_msgs::Path>("reference_path", 1, /*latch=*/true);
  if (path_file.empty()) {
    path_sub_ = nh.subscribe("path", 1, &PathFollowerNode::onPath, this);
    ROS_INFO("flagella_path_follower: no ~path file; waiting for a nav_msgs/Path on %s",
             path_sub_.getTopic().c_str());
  }
  imu_sub_ = nh.subscribe("imu", kQueue, &PathFollowerNode::onImu, this);
  watchdog_ = std::make_unique<StartupWatchdog>(nh, pnh, imu_sub_.getTopic());
  fix_sub_ = nh.subscribe("camera_fix", kQueue, &PathFollowerNode::onCameraFix, this);
}

void PathFollowerNode::build(flagella::control::PathSpec spec) {
  ROS_INFO("flagella_path_follower: %s, %s", controller_options_.mode.c_str(),
           spec.description.c_str());
  controller_ =
      flagella::control::makePathController(std::move(spec), calibration_, controller_options_);
  if (const auto* horizon =
          dynamic_cast<const flagella::control::RecedingHorizonController*>(controller_.get()))
    ROS_INFO(
        "flagella_path_follower: planned on the calibrated model: tracking bound max %.1f mm, "
        "RMS %.1f mm",
        1e3 * horizon->bound().best_max.max_error, 1e3 * horizon->bound().best_rms.rms_error);
  reference_published_ = false;
}

void PathFollowerNode::onPath(const nav_msgs::Path& msg) {
  // A nav_msgs/Path is a polyline in the world frame (its poses' positions; z is ignored).
  std::vector<flagella::control::Vec2> points;
  for (const auto& pose : msg.poses) {
    const flagella::control::Vec2 p(pose.pose.position.x, pose.pose.position.y);
    if (points.empty() || (p - points.back()).norm() > 1e-9) points.push_back(p);
  }
  try {
    flagella::control::PathSpec spec;
    spec.path = flagella::control::Path::polyline(points, false);
    spec.frame = flagella::control::PathFrame::World;
    spec.description =
        "nav_msgs/Path of " + std::to_string(points.size()) + " points (world frame)";
    build(std::move(spec));
  } catch (const std::exception& e) {
    ROS_ERROR("flagella_path_follower: path rejected: %s", e.what());
  }
}

void PathFollowerNode::onCameraFix(const geometry_msgs::PointStamped& msg) {
  fix_.offer(msg.point.x, msg.point.y, msg.point.z, msg.header.stamp.toSec(),
             /*with_height=*/false);
}

void PathFollowerNode::onImu(const sensor_msgs::Imu& msg) {
  watchdog_->heard();
  if (!controller_) return;
  imuToInputs(msg, inputs_);
  const ControllerOutputs out = stepWithLatestFix(*controller_, inputs_, fix_);

  flagella_msgs::MotorCommand command;
  command.header.stamp = msg.header.stamp;  // lockstep: answers the IMU sample of this stamp
  command.header.frame_id = msg.header.frame_id;
  command.omega = out.motor_command;
  motor_pub_.publish(command);

  if (controller_->status().anchored && !reference_published_) publishReference(msg.header.stamp);
  publishStatus(msg.header.stamp, out);
  if (out.mode == ControllerMode::Finished && finished_at_ < 0.0) {
    finished_at_ = inputs_.time;
    ROS_INFO("flagella_path_follower: path complete at t = %.2f s", inputs_.time);
  }
  if (exit_when_finished_ && finished_at_ >= 0.0 && inputs_.time - finished_at_ >= linger_)
    ros::shutdown();
}

void PathFollowerNode::publishStatus(const ros::Time& stamp, const ControllerOutputs& out) {
  const double t = stamp.toSec();
  if (out.mode == last_mode_ && t - last_status_time_ < status_period_ - 1e-9) return;
  last_mode_ = out.mode;
  last_status_time_ = t;
  const flagella::control::PathStatus& s = controller_->status();
  flagella_msgs::ControllerStatus status;
  status.header.stamp = stamp;
  status.header.frame_id = world_frame_;
  status.controller = controller_->name();
  status.mode = toStatusMode(out.mode);
  status.segment_index = s.anchored ? s.element : -1;
  status.progress = s.progress;
  status.cross_track_error = s.cross_track;
  status.heading_error = s.heading_error;
  status.motor_command = out.motor_command;
  status.message = s.message;
  status_pub_.publish(status);
}

void PathFollowerNode::publishReference(const ros::Time& stamp) {
  nav_msgs::Path path;
  path.header.stamp = stamp;
  path.header.frame_id = world_frame_;
  for (const auto& p : controller_->worldPath().sample(kReferenceSpacing)) {
    geometry_msgs::PoseStamped pose;
    pose.header = path.header;
    pose.pose.position.x = p.x();
    pose.pose.position.y = p.y();
    pose.pose.orientation.w = 1.0;
    path.poses.push_back(pose);
  }
  reference_pub_.publish(path);
  reference_published_ = true;
}

}  // namespace flagella::control::node
