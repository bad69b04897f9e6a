#include "flagella_sim/lcm_io/lcm_messages.h"

#include <cmath>

namespace flagella {

namespace {
constexpr double kNanosecondsPerSecond = 1e9;

flagella_lcm::point_t point(const Vec3& x) {
  flagella_lcm::point_t p;
  p.x = x.x(), p.y = x.y(), p.z = x.z();
  return p;
}
flagella_lcm::vector3_t vector3(const Vec3& x) {
  flagella_lcm::vector3_t v;
  v.x = x.x(), v.y = x.y(), v.z = x.z();
  return v;
}
flagella_lcm::quaternion_t quaternion(const Eigen::Quaterniond& q) {
  flagella_lcm::quaternion_t out;
  out.x = q.x(), out.y = q.y(), out.z = q.z(), out.w = q.w();
  return out;
}
flagella_lcm::node_group_t group(const std::string& name, const std::vector<int>& nodes) {
  flagella_lcm::node_group_t g;
  g.name = name;
  g.nodes.assign(nodes.begin(), nodes.end());
  g.num_nodes = static_cast<int32_t>(g.nodes.size());
  return g;
}
void diagonal(double variance, double (&covariance)[9]) {
  for (double& c : covariance) c = 0.0;
  covariance[0] = covariance[4] = covariance[8] = variance;
}
}  // namespace

LcmChannels LcmChannels::withPrefix(const std::string& prefix) {
  return {prefix + "ROD_STATE",         prefix + "IMU",
          prefix + "MOTOR_COMMAND",     prefix + "SLIDER_COMMAND",
          prefix + "CONTROLLER_STATUS", prefix + "CAMERA_FIX"};
}

flagella_lcm::header_t lcmHeader(double time, const std::string& frame_id, int seq) {
  flagella_lcm::header_t h;
  h.seq = seq;
  const double whole = std::floor(time);
  h.stamp.sec = static_cast<int32_t>(whole);
  h.stamp.nsec = static_cast<int32_t>(std::lround((time - whole) * kNanosecondsPerSecond));
  if (h.stamp.nsec >= kNanosecondsPerSecond) h.stamp.sec += 1, h.stamp.nsec = 0;
  h.frame_id = frame_id;
  return h;
}

double stampSeconds(const flagella_lcm::header_t& header) {
  return header.stamp.sec + header.stamp.nsec / kNanosecondsPerSecond;
}

flagella_lcm::rod_state_t toRodStateMessage(const RodSnapshot& s, const std::string& world_frame) {
  flagella_lcm::rod_state_t m;
  m.header = lcmHeader(s.time, world_frame);
  m.robot_name = s.robot_name;
  for (const Vec3& x : s.nodes) m.nodes.push_back(point(x));
  m.num_nodes = static_cast<int32_t>(m.nodes.size());
  m.edge_start.assign(s.edge_start.begin(), s.edge_start.end());
  m.edge_end.assign(s.edge_end.begin(), s.edge_end.end());
  m.edge_twist = s.edge_twist;
  for (const auto& q : s.edge_frames) m.edge_frames.push_back(quaternion(q));
  m.num_edges = static_cast<int32_t>(m.edge_start.size());
  m.head = group("head", s.head_nodes);
  for (std::size_t k = 0; k < s.tail_nodes.size(); ++k)
    m.tails.push_back(group("tail" + std::to_string(k), s.tail_nodes[k]));
  m.num_tails = static_cast<int32_t>(m.tails.size());
  m.omega_h = s.omega_h;
  m.omega_t = s.omega_t;
  m.omega_motor = s.omega_motor;
  m.head_angle = s.head_angle;
  m.tail_angle = s.tail_angle;
  m.head_pose.position = point(s.head_position);
  m.head_pose.orientation = quaternion(s.head_orientation);
  return m;
}

flagella_lcm::imu_t toImuMessage(const ImuSample& sample, const std::string& imu_frame) {
  flagella_lcm::imu_t m;
  m.header = lcmHeader(sample.time, imu_frame);
  m.orientation = quaternion(sample.orientation);
  diagonal(sample.orientation_variance, m.orientation_covariance);
  m.angular_velocity = vector3(sample.angular_velocity);
  diagonal(sample.angular_velocity_variance, m.angular_velocity_covariance);
  m.linear_acceleration = vector3(sample.linear_acceleration);
  diagonal(sample.linear_acceleration_variance, m.linear_acceleration_covariance);
  return m;
}

flagella_lcm::point_stamped_t toCameraFixMessage(const CameraFix& fix,
                                                 const std::string& world_frame) {
  flagella_lcm::point_stamped_t m;
  m.header = lcmHeader(fix.time, world_frame);
  m.point = point(Vec3(fix.position.x(), fix.position.y(), fix.height));
  return m;
}

}  // namespace flagella
