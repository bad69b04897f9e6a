// ROS-side views of a rod snapshot: rviz markers, tf transforms, a path pose, diagnostics.
#pragma once

#include <diagnostic_msgs/DiagnosticStatus.h>
#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <visualization_msgs/MarkerArray.h>

#include <string>
#include <vector>

#include "flagella_sim/runtime/rod_snapshot.h"
#include "flagella_sim/runtime/sim_session.h"

namespace flagella::sim_node {

struct MarkerStyle {
  double tail_width = 0.004;  ///< line width of the tails [m]
  double head_width = 0.02;   ///< line width of the rigid head [m]
};

/// Head as a thick grey line strip through the head nodes, each tail as a coloured line strip.
visualization_msgs::MarkerArray rodMarkers(const flagella::RodSnapshot& s, const ros::Time& stamp,
                                           const std::string& world_frame,
                                           const MarkerStyle& style);

/// The moving frames (REP-103, REP-105): <prefix>/odom -> <prefix>/base_link (head centre, x
/// forward = -t^0, y = m2^0, z = m1^0) and base_link -> <prefix>/tail<k> (material frame of
/// each tail's last edge, at the tail tip).
std::vector<geometry_msgs::TransformStamped> rodTransforms(const flagella::RodSnapshot& s,
                                                           const ros::Time& stamp,
                                                           const std::string& prefix);

/// The fixed frames, for /tf_static: world -> <prefix>/odom (identity: the simulator knows the
/// truth, so odometry does not drift) and base_link -> <prefix>/head (the head's material frame
/// m1^0, m2^0, t^0, the IMU's frame).
std::vector<geometry_msgs::TransformStamped> staticFrames(const ros::Time& stamp,
                                                          const std::string& world_frame,
                                                          const std::string& prefix);

geometry_msgs::PoseStamped headPose(const flagella::RodSnapshot& s, const ros::Time& stamp,
                                    const std::string& world_frame);

diagnostic_msgs::DiagnosticStatus sessionStatus(const flagella::SessionHealth& h,
                                                const std::string& name, double sim_time,
                                                double real_time_factor);

}  // namespace flagella::sim_node
