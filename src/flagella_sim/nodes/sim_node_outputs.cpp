// SimNode's outputs: rod state, TF, markers, path, camera fixes and IMU as they fall due,
// diagnostics, the closing summary, simulated time and progress.
#include <diagnostic_msgs/DiagnosticArray.h>
#include <flagella_msgs/RodState.h>
#include <flagella_msgs/lcm_conversions.h>
#include <geometry_msgs/PointStamped.h>
#include <sensor_msgs/Imu.h>
#include <std_msgs/Empty.h>
#include <tf2_msgs/TFMessage.h>
#include <visualization_msgs/MarkerArray.h>

#include <sstream>

#include "flagella_sim/lcm_io/lcm_messages.h"
#include "sim_node.h"

namespace flagella::sim_node {

template <typename M>
void SimNode::publish(ros::Publisher& pub, const M& msg) {
  pub.publish(msg);
  ++published_[pub.getTopic()];
}

void SimNode::publishOutputs(bool force) {
  const ros::Time now = stamp();
  const flagella::DueOutputs due = schedule_.due(session_->time(), force);
  if (!due.any()) return;
  flagella::RodSnapshot snapshot;
  if (due.needsSnapshot()) {
    snapshot = session_->snapshot();
    if (!snapshot.allFinite()) {
      ROS_ERROR("flagella_sim: non-finite state at t = %.6f s; not published", clockTime());
      return;
    }
  }
  if (due.rod_state) {
    flagella_msgs::RodState msg =
        flagella_msgs::toRos(flagella::toRodStateMessage(snapshot, options_.world_frame));
    msg.header.stamp = now;
    msg.robot_name = options_.tf_prefix;  // this robot's instance name, not its config type
    publish(state_pub_, msg);
    tf2_msgs::TFMessage tf;
    tf.transforms = rodTransforms(snapshot, now, options_.tf_prefix);
    publish(tf_pub_, tf);
  }
  if (due.markers)
    publish(marker_pub_, rodMarkers(snapshot, now, options_.world_frame, options_.markers));
  if (due.path) {
    path_.poses.push_back(headPose(snapshot, now, options_.world_frame));
    if (static_cast<int>(path_.poses.size()) > options_.path_max_poses)
      path_.poses.erase(path_.poses.begin());
    path_.header.stamp = now;
    publish(path_pub_, path_);
  }
  // The camera fix before the IMU sample of the same instant: a controller stepping on IMU
  // samples can use the fix at once.
  if (due.camera_fix && session_->cameraAvailable()) {
    const flagella::CameraFix fix = session_->measureCamera();
    if (fix.position.allFinite()) {
      geometry_msgs::PointStamped msg =
          flagella_msgs::toRos(flagella::toCameraFixMessage(fix, options_.world_frame));
      msg.header.stamp = now;
      publish(camera_pub_, msg);
    }
  }
  if (due.imu) {
    const flagella::ImuSample imu = session_->measureImu();
    if (imu.orientation.coeffs().allFinite() && imu.angular_velocity.allFinite() &&
        imu.linear_acceleration.allFinite()) {
      sensor_msgs::Imu msg =
          flagella_msgs::toRos(flagella::toImuMessage(imu, options_.tf_prefix + "/head"));
      msg.header.stamp = now;
      publish(imu_pub_, msg);
      if (options_.lockstep) {
        awaiting_command_ = true;
        awaited_stamp_ = now;
        await_wall_start_ = ros::WallTime::now();
      }
    }
  }
}

void SimNode::publishDiagnostics() {
  diagnostic_msgs::DiagnosticArray array;
  array.header.stamp = stamp();
  const double wall = (ros::WallTime::now() - run_wall_start_).toSec();
  const double rtf = wall > 0.0 ? clockTime() / wall : 0.0;
  array.status.push_back(sessionStatus(session_->health(), status_name_, clockTime(), rtf));
  for (const auto& [topic, count] : published_) {
    diagnostic_msgs::KeyValue kv;
    kv.key = "published " + topic;
    kv.value = std::to_string(count);
    array.status.back().values.push_back(kv);
  }
  if (options_.lockstep) {
    diagnostic_msgs::KeyValue kv;
    kv.key = "lockstep_timeouts";
    kv.value = std::to_string(lockstep_timeouts_);
    array.status.back().values.push_back(kv);
  }
  publish(diag_pub_, array);
}

void SimNode::printSummary() const {
  const double wall = (ros::WallTime::now() - run_wall_start_).toSec();
  long total = 0;
  std::ostringstream topics;
  for (const auto& [topic, count] : published_) {
    total += count;
    topics << " " << topic << "=" << count;
  }
  const flagella::SessionHealth h = session_->health();
  ROS_INFO(
      "flagella_sim: %.3f s simulated in %.3f s wall (%.2fx real time), %ld steps, "
      "%ld Newton iterations, %ld solver failures; %ld messages (%.0f/s):%s",
      clockTime(), wall, wall > 0 ? clockTime() / wall : 0.0, h.steps, h.newton_iterations,
      h.solver_failures, total, wall > 0 ? total / wall : 0.0, topics.str().c_str());
}

void SimNode::publishTime() {
  if (!time_pub_) return;
  rosgraph_msgs::Clock c;
  c.clock = stamp();
  time_pub_.publish(c);
}

void SimNode::logProgress() {
  if (options_.progress_period <= 0.0) return;
  const ros::WallTime now = ros::WallTime::now();
  if ((now - last_progress_).toSec() < options_.progress_period) return;
  last_progress_ = now;
  const double wall = (now - run_wall_start_).toSec();
  std::ostringstream of;
  if (options_.duration > 0.0) of << " of " << options_.duration;
  ROS_INFO("flagella_sim: t = %.1f%s s simulated, %.2fx real time, %ld steps", clockTime(),
           of.str().c_str(), wall > 0 ? clockTime() / wall : 0.0, session_->health().steps);
}

}  // namespace flagella::sim_node
