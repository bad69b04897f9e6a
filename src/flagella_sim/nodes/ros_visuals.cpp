#include "ros_visuals.h"

#include <diagnostic_msgs/KeyValue.h>

#include <array>

namespace flagella::sim_node {

namespace {
constexpr double kMarkerAlpha = 1.0;
// Tail colours cycle through a small palette (RGB).
const std::array<std::array<float, 3>, 4> kTailColours = {
    {{0.95f, 0.45f, 0.10f}, {0.10f, 0.60f, 0.95f}, {0.20f, 0.80f, 0.30f}, {0.85f, 0.20f, 0.75f}}};

geometry_msgs::Point toPoint(const flagella::Vec3& x) {
  geometry_msgs::Point p;
  p.x = x.x(), p.y = x.y(), p.z = x.z();
  return p;
}
geometry_msgs::Quaternion toQuaternion(const Eigen::Quaterniond& q) {
  geometry_msgs::Quaternion out;
  out.x = q.x(), out.y = q.y(), out.z = q.z(), out.w = q.w();
  return out;
}

visualization_msgs::Marker lineStrip(const flagella::RodSnapshot& s, const std::vector<int>& nodes,
                                     const std::string& ns, int id, double width,
                                     const std::array<float, 3>& rgb) {
  visualization_msgs::Marker m;
  m.ns = ns;
  m.id = id;
  m.type = visualization_msgs::Marker::LINE_STRIP;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1.0;
  m.scale.x = width;
  m.color.r = rgb[0], m.color.g = rgb[1], m.color.b = rgb[2], m.color.a = kMarkerAlpha;
  for (int node : nodes) m.points.push_back(toPoint(s.nodes[node]));
  return m;
}

geometry_msgs::TransformStamped transform(const flagella::Vec3& origin,
                                          const Eigen::Quaterniond& rotation,
                                          const ros::Time& stamp, const std::string& parent,
                                          const std::string& child) {
  geometry_msgs::TransformStamped t;
  t.header.stamp = stamp;
  t.header.frame_id = parent;
  t.child_frame_id = child;
  t.transform.translation.x = origin.x();
  t.transform.translation.y = origin.y();
  t.transform.translation.z = origin.z();
  t.transform.rotation = toQuaternion(rotation);
  return t;
}

// The head frame (m1^0, m2^0, t^0) in base_link (x = -t^0, y = m2^0, z = m1^0): -90 deg about
// y, which takes m1^0 to base z and t^0 to base -x.
Eigen::Quaterniond baseFromHead() {
  return Eigen::Quaterniond(Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitY()));
}

diagnostic_msgs::KeyValue keyValue(const std::string& key, const std::string& value) {
  diagnostic_msgs::KeyValue kv;
  kv.key = key;
  kv.value = value;
  return kv;
}
}  // namespace

visualization_msgs::MarkerArray rodMarkers(const flagella::RodSnapshot& s, const ros::Time& stamp,
                                           const std::string& world_frame,
                                           const MarkerStyle& style) {
  visualization_msgs::MarkerArray array;
  // Head: front node, centre, joint (the rigid part along the axis).
  const std::vector<int> head_axis_nodes(
      s.head_nodes.begin(), s.head_nodes.begin() + std::min<std::size_t>(3, s.head_nodes.size()));
  array.markers.push_back(
      lineStrip(s, head_axis_nodes, "head", 0, style.head_width, {0.55f, 0.55f, 0.60f}));
  for (std::size_t k = 0; k < s.tail_nodes.size(); ++k)
    array.markers.push_back(lineStrip(s, s.tail_nodes[k], "tails", static_cast<int>(k),
                                      style.tail_width, kTailColours[k % kTailColours.size()]));
  for (auto& m : array.markers) {
    m.header.stamp = stamp;
    m.header.frame_id = world_frame;
  }
  return array;
}

std::vector<geometry_msgs::TransformStamped> rodTransforms(const flagella::RodSnapshot& s,
                                                           const ros::Time& stamp,
                                                           const std::string& prefix) {
  std::vector<geometry_msgs::TransformStamped> out;
  const std::string base = prefix + "/base_link";
  const Eigen::Quaterniond base_rotation = s.head_orientation * baseFromHead().conjugate();
  out.push_back(transform(s.head_position, base_rotation, stamp, prefix + "/odom", base));
  const Eigen::Quaterniond to_base = base_rotation.conjugate();
  for (std::size_t k = 0; k < s.tail_nodes.size(); ++k) {
    const std::vector<int>& nodes = s.tail_nodes[k];
    if (nodes.size() < 2) continue;
    const int tip = nodes.back();
    const int before_tip = nodes[nodes.size() - 2];
    for (std::size_t j = 0; j < s.edge_start.size(); ++j) {
      const bool tip_edge = (s.edge_start[j] == before_tip && s.edge_end[j] == tip) ||
                            (s.edge_start[j] == tip && s.edge_end[j] == before_tip);
      if (!tip_edge) continue;
      const flagella::Vec3 origin = to_base * (s.nodes[tip] - s.head_position);
      out.push_back(transform(origin, to_base * s.edge_frames[j], stamp, base,
                              prefix + "/tail" + std::to_string(k)));
      break;
    }
  }
  return out;
}

std::vector<geometry_msgs::TransformStamped> staticFrames(const ros::Time& stamp,
                                                          const std::string& world_frame,
                                                          const std::string& prefix) {
  return {transform(flagella::Vec3::Zero(), Eigen::Quaterniond::Identity(), stamp, world_frame,
                    prefix + "/odom"),
          transform(flagella::Vec3::Zero(), baseFromHead(), stamp, prefix + "/base_link",
                    prefix + "/head")};
}

geometry_msgs::PoseStamped headPose(const flagella::RodSnapshot& s, const ros::Time& stamp,
                                    const std::string& world_frame) {
  geometry_msgs::PoseStamped p;
  p.header.stamp = stamp;
  p.header.frame_id = world_frame;
  p.pose.position = toPoint(s.head_position);
  p.pose.orientation = toQuaternion(s.head_orientation);
  return p;
}

diagnostic_msgs::DiagnosticStatus sessionStatus(const flagella::SessionHealth& h,
                                                const std::string& name, double sim_time,
                                                double real_time_factor) {
  diagnostic_msgs::DiagnosticStatus d;
  d.name = name;
  d.hardware_id = "flagella_sim";
  switch (h.level) {
    case flagella::HealthLevel::Ok:
      d.level = diagnostic_msgs::DiagnosticStatus::OK;
      break;
    case flagella::HealthLevel::Warn:
      d.level = diagnostic_msgs::DiagnosticStatus::WARN;
      break;
    case flagella::HealthLevel::Error:
      d.level = diagnostic_msgs::DiagnosticStatus::ERROR;
      break;
  }
  d.message = h.message;
  d.values = {keyValue("sim_time", std::to_string(sim_time)),
              keyValue("real_time_factor", std::to_string(real_time_factor)),
              keyValue("steps", std::to_string(h.steps)),
              keyValue("newton_iterations", std::to_string(h.newton_iterations)),
              keyValue("subdivided_steps", std::to_string(h.subdivided_steps)),
              keyValue("solver_failures", std::to_string(h.solver_failures)),
              keyValue("halted", h.halted ? "true" : "false"),
              keyValue("motor_applied", std::to_string(h.motor_applied)),
              keyValue("motor_accepted", std::to_string(h.motor_accepted)),
              keyValue("motor_rejected", std::to_string(h.motor_rejected)),
              keyValue("failsafe_active", h.failsafe_active ? "true" : "false"),
              keyValue("slider_position", std::to_string(h.slider_position)),
              keyValue("slider_accepted", std::to_string(h.slider_accepted)),
              keyValue("slider_rejected", std::to_string(h.slider_rejected)),
              keyValue("last_rejection", h.last_rejection),
              keyValue("last_solver_failure", h.last_solver_failure)};
  return d;
}

}  // namespace flagella::sim_node
