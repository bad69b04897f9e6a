// Header-only conversions between the ROS messages of flagella_msgs and their LCM twins
// (same field names; LCM's num_* array lengths are filled from the vectors). Both directions
// are lossless, which test/test_lcm_round_trip.cpp checks.
#pragma once

#include <flagella_msgs/ControllerStatus.h>
#include <flagella_msgs/MotorCommand.h>
#include <flagella_msgs/RodState.h>
#include <flagella_msgs/SliderCommand.h>
#include <flagella_msgs/SteeringStatus.h>
#include <geometry_msgs/PointStamped.h>
#include <sensor_msgs/Imu.h>

#include <algorithm>
#include <cstdint>
#include <flagella_lcm/controller_status_t.hpp>
#include <flagella_lcm/imu_t.hpp>
#include <flagella_lcm/motor_command_t.hpp>
#include <flagella_lcm/point_stamped_t.hpp>
#include <flagella_lcm/rod_state_t.hpp>
#include <flagella_lcm/slider_command_t.hpp>
#include <flagella_lcm/steering_status_t.hpp>
#include <vector>

namespace flagella_msgs {

// ---- small types ----------------------------------------------------------------------------
inline flagella_lcm::header_t toLcm(const std_msgs::Header& in) {
  flagella_lcm::header_t out;
  out.seq = static_cast<int32_t>(in.seq);
  out.stamp.sec = static_cast<int32_t>(in.stamp.sec);
  out.stamp.nsec = static_cast<int32_t>(in.stamp.nsec);
  out.frame_id = in.frame_id;
  return out;
}
inline std_msgs::Header toRos(const flagella_lcm::header_t& in) {
  std_msgs::Header out;
  out.seq = static_cast<uint32_t>(in.seq);
  out.stamp.sec = static_cast<uint32_t>(in.stamp.sec);
  out.stamp.nsec = static_cast<uint32_t>(in.stamp.nsec);
  out.frame_id = in.frame_id;
  return out;
}

inline flagella_lcm::point_t toLcm(const geometry_msgs::Point& in) {
  flagella_lcm::point_t out;
  out.x = in.x, out.y = in.y, out.z = in.z;
  return out;
}
inline geometry_msgs::Point toRos(const flagella_lcm::point_t& in) {
  geometry_msgs::Point out;
  out.x = in.x, out.y = in.y, out.z = in.z;
  return out;
}

inline flagella_lcm::vector3_t toLcm(const geometry_msgs::Vector3& in) {
  flagella_lcm::vector3_t out;
  out.x = in.x, out.y = in.y, out.z = in.z;
  return out;
}
inline geometry_msgs::Vector3 toRos(const flagella_lcm::vector3_t& in) {
  geometry_msgs::Vector3 out;
  out.x = in.x, out.y = in.y, out.z = in.z;
  return out;
}

inline flagella_lcm::quaternion_t toLcm(const geometry_msgs::Quaternion& in) {
  flagella_lcm::quaternion_t out;
  out.x = in.x, out.y = in.y, out.z = in.z, out.w = in.w;
  return out;
}
inline geometry_msgs::Quaternion toRos(const flagella_lcm::quaternion_t& in) {
  geometry_msgs::Quaternion out;
  out.x = in.x, out.y = in.y, out.z = in.z, out.w = in.w;
  return out;
}

inline flagella_lcm::pose_t toLcm(const geometry_msgs::Pose& in) {
  flagella_lcm::pose_t out;
  out.position = toLcm(in.position);
  out.orientation = toLcm(in.orientation);
  return out;
}
inline geometry_msgs::Pose toRos(const flagella_lcm::pose_t& in) {
  geometry_msgs::Pose out;
  out.position = toRos(in.position);
  out.orientation = toRos(in.orientation);
  return out;
}

inline flagella_lcm::node_group_t toLcm(const NodeGroup& in) {
  flagella_lcm::node_group_t out;
  out.name = in.name;
  out.nodes.assign(in.nodes.begin(), in.nodes.end());
  out.num_nodes = static_cast<int32_t>(out.nodes.size());
  return out;
}
inline NodeGroup toRos(const flagella_lcm::node_group_t& in) {
  NodeGroup out;
  out.name = in.name;
  out.nodes.assign(in.nodes.begin(), in.nodes.end());
  return out;
}

/// Converts every element of a vector with the overload above.
template <typename Out, typename In>
std::vector<Out> convertAll(const std::vector<In>& in, Out (*convert)(const In&)) {
  std::vector<Out> out;
  out.reserve(in.size());
  for (const In& element : in) out.push_back(convert(element));
  return out;
}

template <typename Array, typename Out>
void copyFixed(const Array& in, Out& out) {
  std::copy(std::begin(in), std::end(in), std::begin(out));
}

// ---- messages -------------------------------------------------------------------------------
inline flagella_lcm::rod_state_t toLcm(const RodState& in) {
  flagella_lcm::rod_state_t out;
  out.header = toLcm(in.header);
  out.robot_name = in.robot_name;
  out.nodes = convertAll<flagella_lcm::point_t, geometry_msgs::Point>(in.nodes, &toLcm);
  out.num_nodes = static_cast<int32_t>(out.nodes.size());
  out.edge_start.assign(in.edge_start.begin(), in.edge_start.end());
  out.edge_end.assign(in.edge_end.begin(), in.edge_end.end());
  out.edge_twist.assign(in.edge_twist.begin(), in.edge_twist.end());
  out.edge_frames =
      convertAll<flagella_lcm::quaternion_t, geometry_msgs::Quaternion>(in.edge_frames, &toLcm);
  out.num_edges = static_cast<int32_t>(out.edge_start.size());
  out.head = toLcm(in.head);
  out.tails = convertAll<flagella_lcm::node_group_t, NodeGroup>(in.tails, &toLcm);
  out.num_tails = static_cast<int32_t>(out.tails.size());
  out.omega_h = in.omega_h;
  out.omega_t = in.omega_t;
  out.omega_motor = in.omega_motor;
  out.head_angle = in.head_angle;
  out.tail_angle = in.tail_angle;
  out.head_pose = toLcm(in.head_pose);
  return out;
}
inline RodState toRos(const flagella_lcm::rod_state_t& in) {
  RodState out;
  out.header = toRos(in.header);
  out.robot_name = in.robot_name;
  out.nodes = convertAll<geometry_msgs::Point, flagella_lcm::point_t>(in.nodes, &toRos);
  out.edge_start.assign(in.edge_start.begin(), in.edge_start.end());
  out.edge_end.assign(in.edge_end.begin(), in.edge_end.end());
  out.edge_twist.assign(in.edge_twist.begin(), in.edge_twist.end());
  out.edge_frames =
      convertAll<geometry_msgs::Quaternion, flagella_lcm::quaternion_t>(in.edge_frames, &toRos);
  out.head = toRos(in.head);
  out.tails = convertAll<NodeGroup, flagella_lcm::node_group_t>(in.tails, &toRos);
  out.omega_h = in.omega_h;
  out.omega_t = in.omega_t;
  out.omega_motor = in.omega_motor;
  out.head_angle = in.head_angle;
  out.tail_angle = in.tail_angle;
  out.head_pose = toRos(in.head_pose);
  return out;
}

inline flagella_lcm::motor_command_t toLcm(const MotorCommand& in) {
  flagella_lcm::motor_command_t out;
  out.header = toLcm(in.header);
  out.omega = in.omega;
  return out;
}
inline MotorCommand toRos(const flagella_lcm::motor_command_t& in) {
  MotorCommand out;
  out.header = toRos(in.header);
  out.omega = in.omega;
  return out;
}

inline flagella_lcm::slider_command_t toLcm(const SliderCommand& in) {
  flagella_lcm::slider_command_t out;
  out.header = toLcm(in.header);
  out.position = in.position;
  return out;
}
inline SliderCommand toRos(const flagella_lcm::slider_command_t& in) {
  SliderCommand out;
  out.header = toRos(in.header);
  out.position = in.position;
  return out;
}

inline flagella_lcm::controller_status_t toLcm(const ControllerStatus& in) {
  flagella_lcm::controller_status_t out;
  out.header = toLcm(in.header);
  out.controller = in.controller;
  out.mode = static_cast<int8_t>(in.mode);
  out.segment_index = in.segment_index;
  out.progress = in.progress;
  out.cross_track_error = in.cross_track_error;
  out.heading_error = in.heading_error;
  out.motor_command = in.motor_command;
  out.message = in.message;
  return out;
}
inline ControllerStatus toRos(const flagella_lcm::controller_status_t& in) {
  ControllerStatus out;
  out.header = toRos(in.header);
  out.controller = in.controller;
  out.mode = static_cast<uint8_t>(in.mode);
  out.segment_index = in.segment_index;
  out.progress = in.progress;
  out.cross_track_error = in.cross_track_error;
  out.heading_error = in.heading_error;
  out.motor_command = in.motor_command;
  out.message = in.message;
  return out;
}

// The same fields in the same order both ways (the schema test checks the order).
template <typename To, typename From>
void copySteeringStatusFields(const From& in, To& out) {
  out.mode_name = in.mode_name;
  out.waypoint = in.waypoint;
  out.reached = in.reached;
  out.total = in.total;
  out.distance = in.distance;
  out.azimuth_error = in.azimuth_error;
  out.elevation = in.elevation;
  out.target_elevation = in.target_elevation;
  out.motor_command = in.motor_command;
  out.slider_command = in.slider_command;
  out.buckle_cycles = in.buckle_cycles;
  out.in_cycle = in.in_cycle;
  out.flipping = in.flipping;
  out.imu_stale = in.imu_stale;
  out.fix_stale = in.fix_stale;
  out.slider_saturated = in.slider_saturated;
  out.pitching = in.pitching;
  out.crab = in.crab;
  out.neutral = in.neutral;
  out.steer_offset = in.steer_offset;
  out.trim_neutral = in.trim_neutral;
  out.trimmed = in.trimmed;
  out.pitch_neutral = in.pitch_neutral;
  out.pitch_gain = in.pitch_gain;
  out.retrims = in.retrims;
  out.message = in.message;
}
inline flagella_lcm::steering_status_t toLcm(const SteeringStatus& in) {
  flagella_lcm::steering_status_t out;
  out.header = toLcm(in.header);
  out.mode = static_cast<int8_t>(in.mode);
  out.estimated_position = toLcm(in.estimated_position);
  copySteeringStatusFields(in, out);
  return out;
}
inline SteeringStatus toRos(const flagella_lcm::steering_status_t& in) {
  SteeringStatus out;
  out.header = toRos(in.header);
  out.mode = static_cast<uint8_t>(in.mode);
  out.estimated_position = toRos(in.estimated_position);
  copySteeringStatusFields(in, out);
  return out;
}

inline flagella_lcm::point_stamped_t toLcm(const geometry_msgs::PointStamped& in) {
  flagella_lcm::point_stamped_t out;
  out.header = toLcm(in.header);
  out.point = toLcm(in.point);
  return out;
}
inline geometry_msgs::PointStamped toRos(const flagella_lcm::point_stamped_t& in) {
  geometry_msgs::PointStamped out;
  out.header = toRos(in.header);
  out.point = toRos(in.point);
  return out;
}

inline flagella_lcm::imu_t toLcm(const sensor_msgs::Imu& in) {
  flagella_lcm::imu_t out;
  out.header = toLcm(in.header);
  out.orientation = toLcm(in.orientation);
  copyFixed(in.orientation_covariance, out.orientation_covariance);
  out.angular_velocity = toLcm(in.angular_velocity);
  copyFixed(in.angular_velocity_covariance, out.angular_velocity_covariance);
  out.linear_acceleration = toLcm(in.linear_acceleration);
  copyFixed(in.linear_acceleration_covariance, out.linear_acceleration_covariance);
  return out;
}
inline sensor_msgs::Imu toRos(const flagella_lcm::imu_t& in) {
  sensor_msgs::Imu out;
  out.header = toRos(in.header);
  out.orientation = toRos(in.orientation);
  copyFixed(in.orientation_covariance, out.orientation_covariance);
  out.angular_velocity = toRos(in.angular_velocity);
  copyFixed(in.angular_velocity_covariance, out.angular_velocity_covariance);
  out.linear_acceleration = toRos(in.linear_acceleration);
  copyFixed(in.linear_acceleration_covariance, out.linear_acceleration_covariance);
  return out;
}

}  // namespace flagella_msgs
