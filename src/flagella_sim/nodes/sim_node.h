// The simulator node: a thin ROS shell around flagella::SimSession. Parameters in, messages out,
// /clock, services. See the README's "ROS interface" section for every topic and parameter.
#pragma once

#include <flagella_msgs/MotorCommand.h>
#include <flagella_msgs/SliderCommand.h>
#include <nav_msgs/Path.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Clock.h>
#include <std_srvs/SetBool.h>
#include <std_srvs/Trigger.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "flagella_sim/runtime/log_throttle.h"
#include "flagella_sim/runtime/output_schedule.h"
#include "flagella_sim/runtime/sim_session.h"
#include "ros_visuals.h"

namespace flagella::sim_node {

constexpr double kRejectionLogPeriod = 2.0;  ///< [s wall] between lines about rejected commands

struct SimNodeOptions {
  std::string config_path;
  std::string world_frame = "world";
  std::string tf_prefix;          ///< frames <tf_prefix>/head, <tf_prefix>/tail<k>
  double real_time_factor = 1.0;  ///< 0: as fast as possible
  bool publish_clock = true;      ///< false: follow /clock published by another node
  double state_rate = 20.0, marker_rate = 10.0, path_rate = 5.0;  ///< IMU: in SessionOptions
  double diagnostics_rate = 1.0;                                  ///< [Hz of simulated time]
  int path_max_poses = 10000;
  double duration = 0.0;              ///< stop after this much simulated time; 0: run until killed
  bool wait_for_subscribers = false;  ///< hold t = 0 until every output topic has a subscriber
  double wait_timeout = 30.0;         ///< [s wall] then start anyway, with a warning
  /// Hold t = 0 until a message on this topic (flagella_record's latched ~ready); "" = no wait.
  std::string wait_for_recorder;
  /// Software in the loop: after an IMU sample stamped t, hold the next step until a
  /// motor_command stamped >= t has arrived (or lockstep_timeout wall seconds have passed;
  /// wait_timeout before the first command: the controller may still be starting).
  bool lockstep = false;
  /// Lockstep also waits for a slider_command stamped >= t (a controller that commands the
  /// slider every step): the step then never depends on which command the network delivers first.
  bool lockstep_slider = false;
  double lockstep_timeout = 5.0;  ///< [s wall]
  double progress_period = 10.0;  ///< [s wall] between progress lines; 0: none
  /// Clock leader: the sim nodes following its /clock (e.g. "/robot_b/sim"); each step waits
  /// until every follower has reached the leader's time (their ~time), so at
  /// real_time_factor 0 the robots still share one simulated time.
  std::vector<std::string> followers;
  MarkerStyle markers;
};

class SimNode {
 public:
  /// Reads parameters from the private handle; throws flagella::ConfigError on bad input.
  SimNode(ros::NodeHandle& nh, ros::NodeHandle& private_nh);
  /// Runs until ros::ok() turns false or `duration` is reached. Returns the process exit code.
  int run();

 private:
  void onMotorCommand(const flagella_msgs::MotorCommand& msg);
  void onSliderCommand(const flagella_msgs::SliderCommand& msg);
  void onClock(const rosgraph_msgs::Clock& msg);
  /// True when every follower has reached this node's time (or was given up as lost).
  bool followersCaughtUp();
  bool onReset(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res);
  /// ~reconfigure: the session rebuilt from the config with the ~overrides now on the parameter
  /// server, restarted like a reset; a bad override leaves the running session as it was.
  bool onReconfigure(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res);
  /// Restarts the output schedules, the path and the pacing at the session's initial state.
  void restartOutputs();
  /// The model's named parameters onto the parameter server, ~model/<section>/<field>.
  void mirrorModelParameters();
  bool onPause(std_srvs::SetBool::Request& req, std_srvs::SetBool::Response& res);

  bool waitForSubscribers();
  bool readyToStep();
  bool lockstepReady();
  void publishOutputs(bool force);
  void publishDiagnostics();
  void printSummary() const;
  /// One INFO line (simulated time, real-time factor) every progress_period wall seconds.
  void logProgress();
  /// A follower's ~time: its simulated time, at t = 0 and after every step.
  void publishTime();
  double clockTime() const { return time_offset_ + session_->time(); }
  ros::Time stamp() const { return ros::Time(clockTime()); }
  template <typename M>
  void publish(ros::Publisher& pub, const M& msg);

  ros::NodeHandle private_nh_;  ///< ~: parameters read again at reconfigure
  SimNodeOptions options_;
  std::unique_ptr<flagella::SimSession> session_;
  std::string status_name_;

  ros::Publisher tf_static_pub_;  ///< latched: world -> odom, base_link -> head
  ros::Publisher clock_pub_, state_pub_, imu_pub_, marker_pub_, path_pub_, tf_pub_, diag_pub_,
      camera_pub_;
  ros::Subscriber motor_sub_, slider_sub_, clock_sub_;
  ros::Publisher time_pub_;  ///< a follower's own simulated time, after every step
  struct Follower {
    std::string name;
    ros::Subscriber time_sub;
    double time = -1.0;  ///< latest ~time heard; < 0: none yet
    bool lost = false;   ///< silent for lockstep_timeout: no longer waited for
  };
  std::vector<std::unique_ptr<Follower>> followers_;
  ros::WallTime follower_wait_start_;
  bool waiting_for_followers_ = false;
  ros::ServiceServer reset_srv_, pause_srv_, reconfigure_srv_;

  /// What is due when; the IMU and camera rates are the first session's (kept at reconfigure).
  flagella::OutputSchedule schedule_;
  nav_msgs::Path path_;
  std::map<std::string, long> published_;  ///< messages published per topic
  double time_offset_ = 0.0;  ///< simulated time before the last reset (the clock never jumps back)
  double followed_clock_ = 0.0;
  bool paused_ = false;
  bool was_halted_ = false;
  ros::WallTime pace_wall_start_;
  double pace_sim_start_ = 0.0;
  ros::WallTime run_wall_start_;
  ros::WallTime last_progress_;
  // Lockstep: the IMU stamp the next step waits for, and the newest command stamp seen.
  bool awaiting_command_ = false;
  ros::Time awaited_stamp_;
  ros::WallTime await_wall_start_;
  /// The newest stamp heard on a command topic.
  struct NewestStamp {
    bool seen = false;
    ros::Time stamp;
    void hear(const ros::Time& t) {
      if (!seen || t > stamp) stamp = t;
      seen = true;
    }
  };
  NewestStamp motor_stamp_, slider_stamp_;
  long lockstep_timeouts_ = 0;
  // Logging: rejected commands at most once per kRejectionLogPeriod of wall time, failsafe
  // engage and release once each.
  flagella::LogThrottle rejection_log_{kRejectionLogPeriod};
  bool failsafe_logged_ = false;
  void logRejection();
  void logFailsafeChange();
};

}  // namespace flagella::sim_node
