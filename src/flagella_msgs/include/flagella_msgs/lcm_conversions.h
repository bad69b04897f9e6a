// Header-only conversions between the ROS messages of flagella_msgs and their LCM twins, driven
// by one list of fields per message (FLAGELLA_LCM_TWIN below): the same list copies both ways,
// field by field, through Convert<From, To> (numbers cast, strings, variable arrays element by
// element, fixed arrays, nested twins); LCM's num_* array lengths are filled from the arrays.
// Both directions are lossless, and each list is the .msg file's field list, in order, both of
// which test/test_lcm_round_trip.cpp checks.
#pragma once

#include <flagella_msgs/ControllerStatus.h>
#include <flagella_msgs/MotorCommand.h>
#include <flagella_msgs/RodState.h>
#include <flagella_msgs/SliderCommand.h>
#include <flagella_msgs/SteeringStatus.h>
#include <geometry_msgs/PointStamped.h>
#include <sensor_msgs/Imu.h>

#include <boost/array.hpp>
#include <cstddef>
#include <cstdint>
#include <flagella_lcm/controller_status_t.hpp>
#include <flagella_lcm/imu_t.hpp>
#include <flagella_lcm/motor_command_t.hpp>
#include <flagella_lcm/point_stamped_t.hpp>
#include <flagella_lcm/rod_state_t.hpp>
#include <flagella_lcm/slider_command_t.hpp>
#include <flagella_lcm/steering_status_t.hpp>
#include <string>
#include <type_traits>
#include <vector>

namespace flagella_msgs {

namespace lcm_twin {

/// Copies one field's value from `in` to `out` (specialised below and by FLAGELLA_LCM_TWIN).
template <typename From, typename To, typename Enable = void>
struct Convert;

template <typename From, typename To>
void convert(const From& in, To& out) {
  Convert<From, To>::apply(in, out);
}

/// The twin types (set by FLAGELLA_LCM_TWIN).
template <typename Ros>
struct LcmOf;
template <typename Lcm>
struct RosOf;

// Numbers (and the message enums, uint8 in ROS and int8 in LCM): a cast.
template <typename From, typename To>
struct Convert<From, To, std::enable_if_t<std::is_arithmetic_v<From> && std::is_arithmetic_v<To>>> {
  static void apply(const From& in, To& out) { out = static_cast<To>(in); }
};
template <>
struct Convert<std::string, std::string> {
  static void apply(const std::string& in, std::string& out) { out = in; }
};
// Variable-length arrays: element by element.
template <typename A, typename AllocA, typename B, typename AllocB>
struct Convert<std::vector<A, AllocA>, std::vector<B, AllocB>> {
  static void apply(const std::vector<A, AllocA>& in, std::vector<B, AllocB>& out) {
    out.resize(in.size());
    for (std::size_t i = 0; i < in.size(); ++i) convert(in[i], out[i]);
  }
};
// Fixed-length arrays (ROS boost::array, LCM C array).
template <typename A, typename B, std::size_t N>
struct Convert<boost::array<A, N>, B[N]> {
  static void apply(const boost::array<A, N>& in, B (&out)[N]) {
    for (std::size_t i = 0; i < N; ++i) convert(in[i], out[i]);
  }
};
template <typename A, typename B, std::size_t N>
struct Convert<A[N], boost::array<B, N>> {
  static void apply(const A (&in)[N], boost::array<B, N>& out) {
    for (std::size_t i = 0; i < N; ++i) convert(in[i], out[i]);
  }
};

/// The names of a twin's fields, in its list's order (test_lcm_round_trip compares them with the
/// .msg files).
template <typename Ros>
struct FieldNames;

}  // namespace lcm_twin

#define FLAGELLA_LCM_COPY(field) ::flagella_msgs::lcm_twin::convert(in.field, out.field);
#define FLAGELLA_LCM_NAME(field) #field,
#define FLAGELLA_LCM_COUNT(count, array) out.count = static_cast<int32_t>(out.array.size());
#define FLAGELLA_LCM_NO_COUNTS(COUNT)

/// One twin: ROS type, LCM type, the list of fields (FIELDS(X) applies X to each, in order) and
/// LCM's array lengths (COUNTS(C) applies C(num_field, array)).
#define FLAGELLA_LCM_TWIN(Ros, Lcm, FIELDS, COUNTS)                               \
  namespace lcm_twin {                                                            \
  template <>                                                                     \
  struct LcmOf<Ros> {                                                             \
    using type = Lcm;                                                             \
  };                                                                              \
  template <>                                                                     \
  struct RosOf<Lcm> {                                                             \
    using type = Ros;                                                             \
  };                                                                              \
  template <>                                                                     \
  struct Convert<Ros, Lcm> {                                                      \
    static void apply(const Ros& in, Lcm& out) {                                  \
      FIELDS(FLAGELLA_LCM_COPY)                                                   \
      COUNTS(FLAGELLA_LCM_COUNT)                                                  \
    }                                                                             \
  };                                                                              \
  template <>                                                                     \
  struct Convert<Lcm, Ros> {                                                      \
    static void apply(const Lcm& in, Ros& out) { FIELDS(FLAGELLA_LCM_COPY) }      \
  };                                                                              \
  template <>                                                                     \
  struct FieldNames<Ros> {                                                        \
    static std::vector<std::string> get() { return {FIELDS(FLAGELLA_LCM_NAME)}; } \
  };                                                                              \
  }

// ---- the field lists: one per message, in the .msg file's order ------------------------------
// clang-format off
#define FLAGELLA_STAMP_FIELDS(X) X(sec) X(nsec)
#define FLAGELLA_HEADER_FIELDS(X) X(seq) X(stamp) X(frame_id)
#define FLAGELLA_POINT_FIELDS(X) X(x) X(y) X(z)
#define FLAGELLA_QUATERNION_FIELDS(X) X(x) X(y) X(z) X(w)
#define FLAGELLA_POSE_FIELDS(X) X(position) X(orientation)
#define FLAGELLA_NODE_GROUP_FIELDS(X) X(name) X(nodes)
#define FLAGELLA_NODE_GROUP_COUNTS(C) C(num_nodes, nodes)
#define FLAGELLA_ROD_STATE_FIELDS(X) X(header) X(robot_name) X(nodes) X(edge_start) X(edge_end) \
  X(edge_twist) X(edge_frames) X(head) X(tails) X(omega_h) X(omega_t) X(omega_motor)            \
  X(head_angle) X(tail_angle) X(head_pose)
#define FLAGELLA_ROD_STATE_COUNTS(C) C(num_nodes, nodes) C(num_edges, edge_start) \
  C(num_tails, tails)
#define FLAGELLA_MOTOR_COMMAND_FIELDS(X) X(header) X(omega)
#define FLAGELLA_SLIDER_COMMAND_FIELDS(X) X(header) X(position)
#define FLAGELLA_CONTROLLER_STATUS_FIELDS(X) X(header) X(controller) X(mode) X(segment_index) \
  X(progress) X(cross_track_error) X(heading_error) X(motor_command) X(message)
#define FLAGELLA_STEERING_STATUS_FIELDS(X) X(header) X(mode) X(mode_name) X(waypoint) X(reached) \
  X(total) X(distance) X(azimuth_error) X(elevation) X(target_elevation) X(estimated_position)  \
  X(motor_command) X(slider_command) X(buckle_cycles) X(in_cycle) X(flipping) X(imu_stale)      \
  X(fix_stale) X(slider_saturated) X(pitching) X(crab) X(neutral) X(steer_offset)               \
  X(trim_neutral) X(trimmed) X(pitch_neutral) X(pitch_gain) X(retrims) X(message)
#define FLAGELLA_POINT_STAMPED_FIELDS(X) X(header) X(point)
#define FLAGELLA_IMU_FIELDS(X) X(header) X(orientation) X(orientation_covariance) \
  X(angular_velocity) X(angular_velocity_covariance) X(linear_acceleration)       \
  X(linear_acceleration_covariance)
// clang-format on

FLAGELLA_LCM_TWIN(ros::Time, flagella_lcm::stamp_t, FLAGELLA_STAMP_FIELDS, FLAGELLA_LCM_NO_COUNTS)
FLAGELLA_LCM_TWIN(std_msgs::Header, flagella_lcm::header_t, FLAGELLA_HEADER_FIELDS,
                  FLAGELLA_LCM_NO_COUNTS)
FLAGELLA_LCM_TWIN(geometry_msgs::Point, flagella_lcm::point_t, FLAGELLA_POINT_FIELDS,
                  FLAGELLA_LCM_NO_COUNTS)
FLAGELLA_LCM_TWIN(geometry_msgs::Vector3, flagella_lcm::vector3_t, FLAGELLA_POINT_FIELDS,
                  FLAGELLA_LCM_NO_COUNTS)
FLAGELLA_LCM_TWIN(geometry_msgs::Quaternion, flagella_lcm::quaternion_t, FLAGELLA_QUATERNION_FIELDS,
                  FLAGELLA_LCM_NO_COUNTS)
FLAGELLA_LCM_TWIN(geometry_msgs::Pose, flagella_lcm::pose_t, FLAGELLA_POSE_FIELDS,
                  FLAGELLA_LCM_NO_COUNTS)
FLAGELLA_LCM_TWIN(NodeGroup, flagella_lcm::node_group_t, FLAGELLA_NODE_GROUP_FIELDS,
                  FLAGELLA_NODE_GROUP_COUNTS)
FLAGELLA_LCM_TWIN(RodState, flagella_lcm::rod_state_t, FLAGELLA_ROD_STATE_FIELDS,
                  FLAGELLA_ROD_STATE_COUNTS)
FLAGELLA_LCM_TWIN(MotorCommand, flagella_lcm::motor_command_t, FLAGELLA_MOTOR_COMMAND_FIELDS,
                  FLAGELLA_LCM_NO_COUNTS)
FLAGELLA_LCM_TWIN(SliderCommand, flagella_lcm::slider_command_t, FLAGELLA_SLIDER_COMMAND_FIELDS,
                  FLAGELLA_LCM_NO_COUNTS)
FLAGELLA_LCM_TWIN(ControllerStatus, flagella_lcm::controller_status_t,
                  FLAGELLA_CONTROLLER_STATUS_FIELDS, FLAGELLA_LCM_NO_COUNTS)
FLAGELLA_LCM_TWIN(SteeringStatus, flagella_lcm::steering_status_t, FLAGELLA_STEERING_STATUS_FIELDS,
                  FLAGELLA_LCM_NO_COUNTS)
FLAGELLA_LCM_TWIN(geometry_msgs::PointStamped, flagella_lcm::point_stamped_t,
                  FLAGELLA_POINT_STAMPED_FIELDS, FLAGELLA_LCM_NO_COUNTS)
FLAGELLA_LCM_TWIN(sensor_msgs::Imu, flagella_lcm::imu_t, FLAGELLA_IMU_FIELDS,
                  FLAGELLA_LCM_NO_COUNTS)

/// The LCM twin of a ROS message (every field, array lengths set).
template <typename Ros>
typename lcm_twin::LcmOf<Ros>::type toLcm(const Ros& in) {
  typename lcm_twin::LcmOf<Ros>::type out;
  lcm_twin::convert(in, out);
  return out;
}
/// The ROS message of an LCM twin.
template <typename Lcm>
typename lcm_twin::RosOf<Lcm>::type toRos(const Lcm& in) {
  typename lcm_twin::RosOf<Lcm>::type out;
  lcm_twin::convert(in, out);
  return out;
}

}  // namespace flagella_msgs
