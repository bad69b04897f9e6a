#include "steering_node.h"

#include <flagella_msgs/MotorCommand.h>
#include <flagella_msgs/SliderCommand.h>
#include <flagella_msgs/SteeringStatus.h>
#include <visualization_msgs/Marker.h>
#include <visualization_msgs/MarkerArray.h>

#include <cmath>
#include <stdexcept>

namespace flagella::control::node {

namespace {

constexpr int kQueue = 1000;
constexpr double kSliderMarkerSize = 0.006;  // [m], drawn size of the slider block
constexpr double kWaypointAlpha = 0.25;

visualization_msgs::Marker marker(const std::string& frame, const ros::Time& stamp,
                                  const std::string& ns, int id, int type) {
  visualization_msgs::Marker m;
  m.header.frame_id = frame;
  m.header.stamp = stamp;
  m.ns = ns;
  m.id = id;
  m.type = type;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1.0;
  return m;
}

}  // namespace

SteeringNode::SteeringNode(ros::NodeHandle& nh, ros::NodeHandle& pnh) {
  world_frame_ = param<std::string>(pnh, "world_frame", "world");
  head_frame_ = param<std::string>(pnh, "head_frame", "flagella/head");
  const std::string calibration_file = fileParam(pnh, "calibration");
  if (calibration_file.empty())
    throw std::invalid_argument("~calibration (a YAML file) is required");
  const std::string waypoints_file = fileParam(pnh, "waypoints");
  if (waypoints_file.empty()) throw std::invalid_argument("~waypoints (a YAML file) is required");
  SteeringGains gains;
  const std::string schedule = param<std::string>(pnh, "schedule", "relax");
  gains.schedule = scheduleFromName(schedule);
  // A gains file first (~gains, SteeringGains::load), then every gain of SteeringGains by its
  // name (steer_by_offset, trim_neutral: 0 or 1).
  const std::string gains_file = fileParam(pnh, "gains");
  if (!gains_file.empty()) gains.load(gains_file);
  for (const std::string& name : SteeringGains::names())
    gains.set(name, param(pnh, name, gains.get(name)));
  controller_ = std::make_unique<MassTransformerController>(
      loadWaypointMission(waypoints_file), loadSteeringCalibration(calibration_file), gains);
  status_period_ = statusPeriod(pnh);
  exit_when_finished_ = param(pnh, "exit_when_finished", false);
  linger_ = param(pnh, "linger", 1.0);
  if (!(linger_ >= 0.0 && linger_ <= 3600.0))
    throw std::invalid_argument("~linger must be in [0, 3600] s, got " + std::to_string(linger_));

  // The slider first: in lockstep the simulator steps as soon as the motor command arrives.
  slider_pub_ = nh.advertise<flagella_msgs::SliderCommand>("slider_command", kQueue);
  motor_pub_ = nh.advertise<flagella_msgs::MotorCommand>("motor_command", kQueue);
  status_pub_ = nh.advertise<flagella_msgs::SteeringStatus>("steering_status", kQueue);
  waypoint_pub_ =
      nh.advertise<visualization_msgs::MarkerArray>("waypoint_markers", 1, /*latch=*/true);
  slider_marker_pub_ = nh.advertise<visualization_msgs::Marker>("slider_marker", 10);
  estimate_pub_ = nh.advertise<nav_msgs::Path>("estimated_path", 1);
  imu_sub_ = nh.subscribe("imu", kQueue, &SteeringNode::onImu, this);
  watchdog_ = std::make_unique<StartupWatchdog>(nh, pnh, imu_sub_.getTopic());
  fix_sub_ = nh.subscribe("camera_fix", kQueue, &SteeringNode::onCameraFix, this);
  estimated_path_.header.frame_id = world_frame_;
  ROS_INFO("flagella_steering_controller: %s, %zu waypoints (tolerance %.1f mm), %s schedule",
           controller_->mission().description.c_str(), controller_->mission().points.size(),
           controller_->mission().tolerance * 1e3, schedule.c_str());
}

void SteeringNode::onCameraFix(const geometry_msgs::PointStamped& msg) {
  fix_.offer(msg.point.x, msg.point.y, msg.point.z, msg.header.stamp.toSec(), /*with_height=*/true);
}

void SteeringNode::onImu(const sensor_msgs::Imu& msg) {
  watchdog_->heard();
  imuToInputs(msg, inputs_);
  const ControllerOutputs out = stepWithLatestFix(*controller_, inputs_, fix_);

  flagella_msgs::SliderCommand slider;
  slider.header.stamp = msg.header.stamp;
  slider.header.frame_id = head_frame_;
  slider.position = out.slider_position;
  slider_pub_.publish(slider);
  flagella_msgs::MotorCommand command;
  command.header.stamp = msg.header.stamp;  // lockstep: answers the IMU sample of this stamp
  command.header.frame_id = msg.header.frame_id;
  command.omega = out.motor_command;
  motor_pub_.publish(command);

  if (controller_->status().mode != SteeringMode::Waiting && !waypoints_published_)
    publishWaypoints(msg.header.stamp);
  publishStatus(msg.header.stamp, out);
  const SteeringMode mode = controller_->status().mode;
  if (mode == SteeringMode::Finished && finished_at_ < 0.0) {
    finished_at_ = inputs_.time;
    ROS_INFO("flagella_steering_controller: all %d waypoints reached at t = %.1f s",
             controller_->status().reached, inputs_.time);
  }
  if (mode == SteeringMode::Fault && finished_at_ < 0.0) {
    finished_at_ = inputs_.time;
    ROS_ERROR("flagella_steering_controller: fault at t = %.1f s: %s", inputs_.time,
              controller_->status().message);
  }
  if (exit_when_finished_ && finished_at_ >= 0.0 && inputs_.time - finished_at_ >= linger_)
    ros::shutdown();
}

void SteeringNode::publishStatus(const ros::Time& stamp, const ControllerOutputs& out) {
  const double t = stamp.toSec();
  const SteeringStatus& s = controller_->status();
  if (s.mode != last_mode_)
    ROS_INFO("flagella_steering_controller: t = %.1f s: %s -> %s (waypoint %d, %s)", t,
             steeringModeName(last_mode_), steeringModeName(s.mode), s.waypoint, s.message);
  if (s.mode == last_mode_ && t - last_status_time_ < status_period_ - 1e-9) return;
  last_mode_ = s.mode;
  last_status_time_ = t;
  flagella_msgs::SteeringStatus status;
  status.header.stamp = stamp;
  status.header.frame_id = world_frame_;
  status.mode = static_cast<std::uint8_t>(s.mode);
  status.mode_name = steeringModeName(s.mode);
  status.waypoint = s.waypoint;
  status.reached = s.reached;
  status.total = static_cast<int>(controller_->mission().points.size());
  status.distance = s.distance;
  status.azimuth_error = s.azimuth_error;
  status.elevation = s.elevation;
  status.target_elevation = s.target_elevation;
  const Vec3& p = controller_->estimatedPosition();
  status.estimated_position.x = p.x();
  status.estimated_position.y = p.y();
  status.estimated_position.z = p.z();
  status.motor_command = out.motor_command;
  status.slider_command = out.slider_position;
  status.buckle_cycles = static_cast<int>(s.cycles);
  status.in_cycle = s.in_cycle;
  status.flipping = s.flipping;
  status.imu_stale = s.imu_stale;
  status.fix_stale = s.fix_stale;
  status.slider_saturated = s.slider_saturated;
  status.pitching = s.pitching;
  status.crab = s.crab;
  status.neutral = s.neutral;
  status.steer_offset = s.steer_offset;
  status.trim_neutral = s.trim_neutral;
  status.trimmed = s.trimmed;
  status.pitch_neutral = s.pitch_neutral;
  status.pitch_gain = s.pitch_gain;
  status.retrims = static_cast<int>(s.retrims);
  status.message = s.message;
  status_pub_.publish(status);
  publishSlider(stamp, out.slider_position);
  if (t - last_estimate_time_ >= estimate_period_ - 1e-9) {
    last_estimate_time_ = t;
    publishEstimate(stamp);
  }
}

void SteeringNode::publishWaypoints(const ros::Time& stamp) {
  // Spheres of the reach tolerance, numbered, and the planned legs as a line strip.
  visualization_msgs::MarkerArray array;
  const double tolerance = controller_->mission().tolerance;
  visualization_msgs::Marker legs =
      marker(world_frame_, stamp, "legs", 0, visualization_msgs::Marker::LINE_STRIP);
  legs.scale.x = 0.001;
  legs.color.r = 1.0, legs.color.g = 0.8, legs.color.b = 0.2, legs.color.a = 1.0;
  geometry_msgs::Point start;
  const Vec3& origin = controller_->estimatedPosition();
  start.x = origin.x(), start.y = origin.y(), start.z = origin.z();
  legs.points.push_back(start);
  int id = 0;
  for (const Vec3& w : controller_->waypoints()) {
    visualization_msgs::Marker sphere =
        marker(world_frame_, stamp, "waypoints", id, visualization_msgs::Marker::SPHERE);
    sphere.pose.position.x = w.x(), sphere.pose.position.y = w.y(), sphere.pose.position.z = w.z();
    sphere.scale.x = sphere.scale.y = sphere.scale.z = 2.0 * tolerance;
    sphere.color.r = 1.0, sphere.color.g = 0.6, sphere.color.b = 0.1;
    sphere.color.a = kWaypointAlpha;
    array.markers.push_back(sphere);
    visualization_msgs::Marker label = marker(world_frame_, stamp, "waypoint_labels", id,
                                              visualization_msgs::Marker::TEXT_VIEW_FACING);
    label.pose.position = sphere.pose.position;
    label.scale.z = 0.3 * tolerance;
    label.color.r = label.color.g = label.color.b = label.color.a = 1.0;
    label.text = std::to_string(id + 1);
    array.markers.push_back(label);
    legs.points.push_back(sphere.pose.position);
    ++id;
  }
  array.markers.push_back(legs);
  waypoint_pub_.publish(array);
  waypoints_published_ = true;
}

void SteeringNode::publishSlider(const ros::Time& stamp, double position) {
  // The slider's block on the head axis (the head frame's z), where it was commanded.
  visualization_msgs::Marker block =
      marker(head_frame_, stamp, "slider", 0, visualization_msgs::Marker::CUBE);
  block.pose.position.z = position;
  block.scale.x = block.scale.y = kSliderMarkerSize;
  block.scale.z = 0.5 * kSliderMarkerSize;
  const bool saturated = controller_->status().slider_saturated;
  block.color.r = saturated ? 1.0 : 0.2, block.color.g = saturated ? 0.2 : 0.6;
  block.color.b = saturated ? 0.2 : 1.0, block.color.a = 1.0;
  slider_marker_pub_.publish(block);
}

void SteeringNode::publishEstimate(const ros::Time& stamp) {
  geometry_msgs::PoseStamped pose;
  pose.header.stamp = stamp;
  pose.header.frame_id = world_frame_;
  const Vec3& p = controller_->estimatedPosition();
  pose.pose.position.x = p.x(), pose.pose.position.y = p.y(), pose.pose.position.z = p.z();
  pose.pose.orientation.w = 1.0;
  estimated_path_.poses.push_back(pose);
  estimated_path_.header.stamp = stamp;
  estimate_pub_.publish(estimated_path_);
}

}  // namespace flagella::control::node
