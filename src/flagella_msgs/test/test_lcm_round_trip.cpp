// The LCM twins carry exactly the ROS schema: same field names in the same order (read from the
// .msg and .lcm files), and every message survives ROS -> LCM wire bytes -> ROS unchanged (and
// the reverse), compared as serialized bytes so no field can be silently dropped.
#include <gtest/gtest.h>
#include <ros/serialization.h>

#include <fstream>
#include <random>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "flagella_msgs/lcm_conversions.h"

namespace {

using namespace flagella_msgs;

std::mt19937 rng(12345);
double anyDouble() { return std::uniform_real_distribution<double>(-1e3, 1e3)(rng); }
int anyInt() { return std::uniform_int_distribution<int>(0, 1 << 30)(rng); }
std::string anyString() { return "s" + std::to_string(anyInt()); }

std_msgs::Header anyHeader() {
  std_msgs::Header h;
  h.seq = anyInt();
  h.stamp.sec = anyInt();
  h.stamp.nsec = anyInt() % 1000000000;
  h.frame_id = anyString();
  return h;
}
geometry_msgs::Point anyPoint() {
  geometry_msgs::Point p;
  p.x = anyDouble(), p.y = anyDouble(), p.z = anyDouble();
  return p;
}
geometry_msgs::Quaternion anyQuaternion() {
  geometry_msgs::Quaternion q;
  q.x = anyDouble(), q.y = anyDouble(), q.z = anyDouble(), q.w = anyDouble();
  return q;
}
NodeGroup anyGroup(int size) {
  NodeGroup g;
  g.name = anyString();
  for (int i = 0; i < size; ++i) g.nodes.push_back(anyInt());
  return g;
}

RodState anyRodState() {
  RodState m;
  m.header = anyHeader();
  m.robot_name = anyString();
  for (int i = 0; i < 17; ++i) m.nodes.push_back(anyPoint());
  for (int j = 0; j < 16; ++j) {
    m.edge_start.push_back(anyInt());
    m.edge_end.push_back(anyInt());
    m.edge_twist.push_back(anyDouble());
    m.edge_frames.push_back(anyQuaternion());
  }
  m.head = anyGroup(4);
  for (int k = 0; k < 3; ++k) m.tails.push_back(anyGroup(5 + k));
  m.omega_h = anyDouble(), m.omega_t = anyDouble(), m.omega_motor = anyDouble();
  m.head_angle = anyDouble(), m.tail_angle = anyDouble();
  m.head_pose.position = anyPoint();
  m.head_pose.orientation = anyQuaternion();
  return m;
}
MotorCommand anyMotorCommand() {
  MotorCommand m;
  m.header = anyHeader();
  m.omega = anyDouble();
  return m;
}
SliderCommand anySliderCommand() {
  SliderCommand m;
  m.header = anyHeader();
  m.position = anyDouble();
  return m;
}
ControllerStatus anyControllerStatus() {
  ControllerStatus m;
  m.header = anyHeader();
  m.controller = anyString();
  m.mode = ControllerStatus::FAULT;
  m.segment_index = anyInt();
  m.progress = anyDouble(), m.cross_track_error = anyDouble(), m.heading_error = anyDouble();
  m.motor_command = anyDouble();
  m.message = anyString();
  return m;
}
SteeringStatus anySteeringStatus() {
  SteeringStatus m;
  m.header = anyHeader();
  m.mode = SteeringStatus::MASS_TRANSFORMER;
  m.mode_name = anyString();
  m.waypoint = anyInt(), m.reached = anyInt(), m.total = anyInt();
  m.distance = anyDouble(), m.azimuth_error = anyDouble(), m.elevation = anyDouble();
  m.target_elevation = anyDouble();
  m.estimated_position = anyPoint();
  m.motor_command = anyDouble(), m.slider_command = anyDouble();
  m.buckle_cycles = anyInt();
  m.in_cycle = true, m.flipping = false, m.imu_stale = true, m.fix_stale = false;
  m.slider_saturated = true;
  m.pitching = true;
  m.crab = anyDouble(), m.neutral = anyDouble(), m.steer_offset = anyDouble();
  m.trim_neutral = anyDouble();
  m.trimmed = true;
  m.pitch_neutral = anyDouble(), m.pitch_gain = anyDouble();
  m.retrims = anyInt();
  m.message = anyString();
  return m;
}
sensor_msgs::Imu anyImu() {
  sensor_msgs::Imu m;
  m.header = anyHeader();
  m.orientation = anyQuaternion();
  m.angular_velocity.x = anyDouble(), m.angular_velocity.y = anyDouble();
  m.angular_velocity.z = anyDouble();
  m.linear_acceleration.x = anyDouble(), m.linear_acceleration.y = anyDouble();
  m.linear_acceleration.z = anyDouble();
  for (int i = 0; i < 9; ++i) {
    m.orientation_covariance[i] = anyDouble();
    m.angular_velocity_covariance[i] = anyDouble();
    m.linear_acceleration_covariance[i] = anyDouble();
  }
  return m;
}

geometry_msgs::PointStamped anyPointStamped() {
  geometry_msgs::PointStamped m;
  m.header = anyHeader();
  m.point = anyPoint();
  return m;
}

template <typename M>
std::vector<uint8_t> rosBytes(const M& message) {
  std::vector<uint8_t> buffer(ros::serialization::serializationLength(message));
  ros::serialization::OStream stream(buffer.data(), static_cast<uint32_t>(buffer.size()));
  ros::serialization::serialize(stream, message);
  return buffer;
}
template <typename L>
std::vector<uint8_t> lcmBytes(const L& message) {
  std::vector<uint8_t> buffer(message.getEncodedSize());
  EXPECT_EQ(message.encode(buffer.data(), 0, static_cast<int>(buffer.size())),
            static_cast<int>(buffer.size()));
  return buffer;
}
template <typename L>
L lcmDecode(const std::vector<uint8_t>& bytes) {
  L message;
  EXPECT_EQ(message.decode(bytes.data(), 0, static_cast<int>(bytes.size())),
            static_cast<int>(bytes.size()));
  return message;
}

/// ROS -> LCM -> encoded bytes -> decoded LCM -> ROS must reproduce the original's bytes, and
/// re-encoding the result in LCM must reproduce the LCM bytes.
template <typename L, typename M>
void expectRoundTrip(const M& original) {
  const std::vector<uint8_t> wire = lcmBytes(toLcm(original));
  const L decoded = lcmDecode<L>(wire);
  const M back = toRos(decoded);
  EXPECT_EQ(rosBytes(original), rosBytes(back));
  EXPECT_EQ(wire, lcmBytes(toLcm(back)));
}

TEST(LcmRoundTrip, RodState) { expectRoundTrip<flagella_lcm::rod_state_t>(anyRodState()); }
TEST(LcmRoundTrip, MotorCommand) {
  expectRoundTrip<flagella_lcm::motor_command_t>(anyMotorCommand());
}
TEST(LcmRoundTrip, SliderCommand) {
  expectRoundTrip<flagella_lcm::slider_command_t>(anySliderCommand());
}
TEST(LcmRoundTrip, ControllerStatus) {
  expectRoundTrip<flagella_lcm::controller_status_t>(anyControllerStatus());
}
TEST(LcmRoundTrip, SteeringStatus) {
  expectRoundTrip<flagella_lcm::steering_status_t>(anySteeringStatus());
}
TEST(LcmRoundTrip, Imu) { expectRoundTrip<flagella_lcm::imu_t>(anyImu()); }
TEST(LcmRoundTrip, PointStamped) {
  expectRoundTrip<flagella_lcm::point_stamped_t>(anyPointStamped());
}

TEST(LcmRoundTrip, EmptyArraysSurvive) {
  RodState empty;
  expectRoundTrip<flagella_lcm::rod_state_t>(empty);
}

// ---- schema twins: field names, in order, from the definition files --------------------------
std::string readFile(const std::string& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << path;
  std::stringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

/// Field names of a message definition: "type name" lines, skipping comments and constants
/// (NAME=value), up to the first "===" line (where full definitions list the nested types).
std::vector<std::string> definitionFields(const std::string& definition) {
  std::vector<std::string> names;
  std::istringstream lines(definition);
  const std::regex field(R"(^\s*[A-Za-z0-9_/]+(\[\d*\])?\s+([A-Za-z0-9_]+)\s*(#.*)?$)");
  std::string line;
  std::smatch match;
  while (std::getline(lines, line)) {
    if (line.rfind("===", 0) == 0) break;
    if (std::regex_match(line, match, field)) names.push_back(match[2]);
  }
  return names;
}

/// Field names of a .msg file.
std::vector<std::string> msgFields(const std::string& path) {
  return definitionFields(readFile(path));
}

/// Field names of a .lcm struct, skipping const declarations and the num_* array lengths.
std::vector<std::string> lcmFields(const std::string& path) {
  std::string text = readFile(path);
  text = std::regex_replace(text, std::regex(R"(//[^\n]*)"), "");
  const std::size_t open = text.find('{');
  const std::size_t close = text.rfind('}');
  std::istringstream body(text.substr(open + 1, close - open - 1));
  std::vector<std::string> names;
  const std::regex field(R"(^\s*[A-Za-z0-9_]+\s+([A-Za-z0-9_]+)(\[[^\]]*\])?\s*$)");
  std::string declaration;
  std::smatch match;
  while (std::getline(body, declaration, ';')) {
    if (declaration.find("const") != std::string::npos) continue;
    if (!std::regex_match(declaration, match, field)) continue;
    const std::string name = match[1];
    if (name.rfind("num_", 0) == 0) continue;
    names.push_back(name);
  }
  return names;
}

struct TwinPair {
  const char* msg;
  const char* lcm;
};

TEST(LcmSchema, TwinsHaveTheSameFieldsInTheSameOrder) {
  const std::string root = FLAGELLA_MSGS_DIR;
  const TwinPair pairs[] = {{"msg/RodState.msg", "lcm/rod_state_t.lcm"},
                            {"msg/NodeGroup.msg", "lcm/node_group_t.lcm"},
                            {"msg/MotorCommand.msg", "lcm/motor_command_t.lcm"},
                            {"msg/SliderCommand.msg", "lcm/slider_command_t.lcm"},
                            {"msg/ControllerStatus.msg", "lcm/controller_status_t.lcm"},
                            {"msg/SteeringStatus.msg", "lcm/steering_status_t.lcm"}};
  for (const TwinPair& pair : pairs) {
    const std::vector<std::string> ros_fields = msgFields(root + "/" + pair.msg);
    ASSERT_GE(ros_fields.size(), 2u) << pair.msg;
    EXPECT_EQ(ros_fields, lcmFields(root + "/" + pair.lcm)) << pair.msg << " vs " << pair.lcm;
  }
  // sensor_msgs/Imu is not ours: its twin must list the standard message's fields.
  const std::vector<std::string> imu_fields = {"header",
                                               "orientation",
                                               "orientation_covariance",
                                               "angular_velocity",
                                               "angular_velocity_covariance",
                                               "linear_acceleration",
                                               "linear_acceleration_covariance"};
  EXPECT_EQ(imu_fields, lcmFields(root + "/lcm/imu_t.lcm"));
  // geometry_msgs/PointStamped (the camera fix) likewise, read from the generated header's full
  // definition text.
  const std::vector<std::string> point_stamped_fields =
      definitionFields(ros::message_traits::Definition<geometry_msgs::PointStamped>::value());
  EXPECT_EQ(point_stamped_fields, (std::vector<std::string>{"header", "point"}));
  EXPECT_EQ(point_stamped_fields, lcmFields(root + "/lcm/point_stamped_t.lcm"));
}

// The converters' field lists (lcm_conversions.h) are the definition files' lists, in order: a
// field added to a .msg and its .lcm but not to the list would otherwise be dropped both ways.
TEST(LcmSchema, ConverterListsAreTheDefinitionFiles) {
  using lcm_twin::FieldNames;
  const std::string root = std::string(FLAGELLA_MSGS_DIR) + "/msg/";
  EXPECT_EQ(FieldNames<RodState>::get(), msgFields(root + "RodState.msg"));
  EXPECT_EQ(FieldNames<NodeGroup>::get(), msgFields(root + "NodeGroup.msg"));
  EXPECT_EQ(FieldNames<MotorCommand>::get(), msgFields(root + "MotorCommand.msg"));
  EXPECT_EQ(FieldNames<SliderCommand>::get(), msgFields(root + "SliderCommand.msg"));
  EXPECT_EQ(FieldNames<ControllerStatus>::get(), msgFields(root + "ControllerStatus.msg"));
  EXPECT_EQ(FieldNames<SteeringStatus>::get(), msgFields(root + "SteeringStatus.msg"));
  // Messages not ours: their full definitions as the generated headers give them.
  using ros::message_traits::Definition;
  EXPECT_EQ(FieldNames<sensor_msgs::Imu>::get(),
            definitionFields(Definition<sensor_msgs::Imu>::value()));
  EXPECT_EQ(FieldNames<geometry_msgs::PointStamped>::get(),
            definitionFields(Definition<geometry_msgs::PointStamped>::value()));
  EXPECT_EQ(FieldNames<geometry_msgs::Pose>::get(),
            definitionFields(Definition<geometry_msgs::Pose>::value()));
  EXPECT_EQ(FieldNames<geometry_msgs::Quaternion>::get(),
            definitionFields(Definition<geometry_msgs::Quaternion>::value()));
  EXPECT_EQ(FieldNames<geometry_msgs::Point>::get(),
            definitionFields(Definition<geometry_msgs::Point>::value()));
  EXPECT_EQ(FieldNames<geometry_msgs::Vector3>::get(),
            definitionFields(Definition<geometry_msgs::Vector3>::value()));
  EXPECT_EQ(FieldNames<std_msgs::Header>::get(),
            definitionFields(Definition<std_msgs::Header>::value()));
}

TEST(LcmSchema, FieldParserSeesEveryRodStateField) {
  // Guards the parser itself: RodState has 15 fields, its twin the same 15 plus 3 array lengths.
  EXPECT_EQ(msgFields(std::string(FLAGELLA_MSGS_DIR) + "/msg/RodState.msg").size(), 15u);
}

}  // namespace
