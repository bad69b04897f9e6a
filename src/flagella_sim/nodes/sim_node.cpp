#include "sim_node.h"

#include <diagnostic_msgs/DiagnosticArray.h>
#include <flagella_msgs/lcm_conversions.h>
#include <ros/callback_queue.h>
#include <std_msgs/Empty.h>
#include <tf2_msgs/TFMessage.h>

#include <sstream>

#include "flagella_sim/runtime/lockstep_gate.h"
#include "flagella_sim/simulation/simulation_config.h"
#include "node_params.h"

namespace flagella::sim_node {

namespace {
constexpr double kIdlePoll = 0.005;      // [s wall] poll period while paused or waiting
constexpr double kMaxPaceSleep = 0.002;  // [s wall] longest sleep while pacing
constexpr double kDrainTime = 1.0;       // [s wall] let subscribers receive the last messages
constexpr double kWallDiagnosticsPeriod = 1.0;  // [s wall] diagnostics while paused or halted
constexpr double kLockstepPoll = 0.001;         // [s wall] longest wait for a callback in lockstep
// Outgoing queue per subscriber: deep enough that a recorder keeps up with a session running
// many times faster than real time (100 Hz IMU at 30x is 3000 messages per second).
constexpr int kQueue = 5000;

/// The lockstep policy with this node's limits.
flagella::LockstepGate lockstepGate(const SimNodeOptions& o) {
  return flagella::LockstepGate({o.wait_timeout, o.lockstep_timeout}, o.lockstep_slider);
}

/// A NewestStamp (ROS stamp) as the gate's plain seconds.
template <typename Stamp>
flagella::HeardStamp heard(const Stamp& s) {
  return {s.seen, s.stamp.toSec()};
}

void sleepWall(double seconds) { ros::WallDuration(seconds).sleep(); }
}  // namespace

SimNode::SimNode(ros::NodeHandle& nh, ros::NodeHandle& pnh)
    : private_nh_(pnh), options_(nodeOptionsFromParams(nh, pnh)) {
  std::string overrides;
  pnh.param<std::string>("overrides", overrides, "");
  const flagella::SimulationConfig config =
      flagella::loadSimulationConfig(options_.config_path, splitOverrides(overrides));
  session_ = std::make_unique<flagella::SimSession>(config, sessionOptionsFromParams(pnh));
  // The session options hold the IMU and camera rates (camera rate 0: no camera, never due).
  flagella::OutputRates rates =
      flagella::OutputRates::forSession(session_->options(), options_.state_rate);
  rates.markers = options_.marker_rate;
  rates.path = options_.path_rate;
  rates.diagnostics = options_.diagnostics_rate;
  schedule_ = flagella::OutputSchedule(rates);
  status_name_ = options_.tf_prefix + ": flagella_sim";

  if (options_.publish_clock)
    clock_pub_ = nh.advertise<rosgraph_msgs::Clock>("/clock", kQueue);
  else {
    clock_sub_ = nh.subscribe("/clock", kQueue, &SimNode::onClock, this);
    time_pub_ = pnh.advertise<rosgraph_msgs::Clock>("time", kQueue);
  }
  for (const std::string& name : options_.followers) {
    auto f = std::make_unique<Follower>();
    f->name = name;
    Follower* raw = f.get();
    f->time_sub = nh.subscribe<rosgraph_msgs::Clock>(
        name + "/time", kQueue,
        [raw](const rosgraph_msgs::Clock::ConstPtr& m) { raw->time = m->clock.toSec(); });
    followers_.push_back(std::move(f));
  }
  state_pub_ = nh.advertise<flagella_msgs::RodState>("rod_state", kQueue);
  imu_pub_ = nh.advertise<sensor_msgs::Imu>("imu", kQueue);
  if (session_->options().camera.enabled())
    camera_pub_ = nh.advertise<geometry_msgs::PointStamped>("camera_fix", kQueue);
  marker_pub_ = nh.advertise<visualization_msgs::MarkerArray>("markers", kQueue);
  path_pub_ = nh.advertise<nav_msgs::Path>("head_path", kQueue);
  tf_pub_ = nh.advertise<tf2_msgs::TFMessage>("/tf", kQueue);
  tf_static_pub_ = nh.advertise<tf2_msgs::TFMessage>("/tf_static", 1, /*latch=*/true);
  tf2_msgs::TFMessage fixed;
  fixed.transforms = staticFrames(ros::Time(0, 1), options_.world_frame, options_.tf_prefix);
  tf_static_pub_.publish(fixed);
  diag_pub_ = nh.advertise<diagnostic_msgs::DiagnosticArray>("/diagnostics", kQueue);
  motor_sub_ = nh.subscribe("motor_command", kQueue, &SimNode::onMotorCommand, this);
  slider_sub_ = nh.subscribe("slider_command", kQueue, &SimNode::onSliderCommand, this);
  reset_srv_ = pnh.advertiseService("reset", &SimNode::onReset, this);
  pause_srv_ = pnh.advertiseService("pause", &SimNode::onPause, this);
  reconfigure_srv_ = pnh.advertiseService("reconfigure", &SimNode::onReconfigure, this);
  mirrorModelParameters();
  path_.header.frame_id = options_.world_frame;

  const auto& net = session_->simulation().network();
  ROS_INFO_STREAM("flagella_sim: "
                  << config.robotType() << " from " << options_.config_path << ", "
                  << net.numNodes() << " nodes, dt " << config.dt << " s, "
                  << (options_.real_time_factor > 0.0
                          ? std::to_string(options_.real_time_factor) + "x real time"
                          : std::string("as fast as possible"))
                  << (options_.publish_clock ? "" : ", following /clock")
                  << (options_.lockstep ? ", lockstep with motor_command" : ""));
}

void SimNode::onMotorCommand(const flagella_msgs::MotorCommand& msg) {
  // Any command answers a lockstep wait (a rejected value too: the gate and failsafe handle it).
  motor_stamp_.hear(msg.header.stamp);
  if (session_->commandMotor(msg.omega) != flagella::CommandVerdict::Accepted) logRejection();
}

void SimNode::onSliderCommand(const flagella_msgs::SliderCommand& msg) {
  slider_stamp_.hear(msg.header.stamp);
  if (session_->commandSlider(msg.position) != flagella::CommandVerdict::Accepted) logRejection();
}

void SimNode::logRejection() {
  long held_back = 0;
  if (!rejection_log_.allow(ros::WallTime::now().toSec(), held_back)) return;
  const flagella::SessionHealth h = session_->health();
  ROS_ERROR_STREAM("flagella_sim: rejected " << h.last_rejection << " (" << h.motor_rejected
                                             << " motor and " << h.slider_rejected
                                             << " slider commands rejected so far; " << held_back
                                             << " not logged since the last line)");
}

void SimNode::logFailsafeChange() {
  const bool active = session_->failsafeActive();
  if (active == failsafe_logged_) return;
  failsafe_logged_ = active;
  if (active)
    ROS_WARN(
        "flagella_sim: failsafe engaged at t = %.3f s: no valid motor command for %.3f s of "
        "simulated time; motor stopped",
        clockTime(), session_->options().command_timeout);
  else
    ROS_INFO("flagella_sim: failsafe released at t = %.3f s: a valid motor command arrived",
             clockTime());
}

void SimNode::onClock(const rosgraph_msgs::Clock& msg) { followed_clock_ = msg.clock.toSec(); }

void SimNode::restartOutputs() {
  failsafe_logged_ = false;
  path_.poses.clear();
  schedule_.restart();
  pace_wall_start_ = ros::WallTime::now();
  pace_sim_start_ = session_->time();
  was_halted_ = false;
}

bool SimNode::onReset(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
  time_offset_ += session_->time();
  session_->reset();
  restartOutputs();
  res.success = true;
  res.message = "robot reset to its initial state at t = " + std::to_string(clockTime()) + " s";
  ROS_INFO_STREAM("flagella_sim: " << res.message);
  publishOutputs(true);
  return true;
}

bool SimNode::onReconfigure(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
  std::string overrides;
  private_nh_.param<std::string>("overrides", overrides, "");
  std::unique_ptr<flagella::SimSession> rebuilt;
  try {
    const flagella::SimulationConfig config =
        flagella::loadSimulationConfig(options_.config_path, splitOverrides(overrides));
    rebuilt = std::make_unique<flagella::SimSession>(config, sessionOptionsFromParams(private_nh_));
  } catch (const std::exception& e) {
    res.success = false;
    res.message = std::string("not reconfigured, the session runs on unchanged: ") + e.what();
    ROS_ERROR_STREAM("flagella_sim: " << res.message);
    return true;
  }
  time_offset_ += session_->time();
  session_ = std::move(rebuilt);
  restartOutputs();
  mirrorModelParameters();
  res.success = true;
  res.message = "reconfigured with overrides \"" + overrides +
                "\", restarted at t = " + std::to_string(clockTime()) + " s";
  ROS_INFO_STREAM("flagella_sim: " << res.message);
  publishOutputs(true);
  return true;
}

void SimNode::mirrorModelParameters() {
  const flagella::Simulation& sim = session_->simulation();
  for (const std::string& name : sim.parameterNames()) {
    std::string key = "model/" + name;
    for (char& c : key)
      if (c == '.') c = '/';
    private_nh_.setParam(key, sim.parameterSpec(name).value);
  }
}

bool SimNode::onPause(std_srvs::SetBool::Request& req, std_srvs::SetBool::Response& res) {
  paused_ = req.data;
  pace_wall_start_ = await_wall_start_ = ros::WallTime::now();
  pace_sim_start_ = session_->time();
  res.success = true;
  res.message = paused_ ? "paused" : "running";
  ROS_INFO_STREAM("flagella_sim: " << res.message << " at t = " << clockTime() << " s");
  return true;
}

bool SimNode::waitForSubscribers() {
  if (!options_.wait_for_subscribers && !options_.lockstep && options_.wait_for_recorder.empty())
    return true;
  const ros::WallTime give_up = ros::WallTime::now() + ros::WallDuration(options_.wait_timeout);
  ros::Publisher* outputs[] = {&state_pub_, &imu_pub_,  &marker_pub_, &path_pub_,
                               &tf_pub_,    &diag_pub_, &camera_pub_};
  bool recorder_ready = options_.wait_for_recorder.empty();
  ros::Subscriber recorder_sub;
  if (!recorder_ready) {
    ros::NodeHandle nh;
    recorder_sub = nh.subscribe<std_msgs::Empty>(
        options_.wait_for_recorder, 1,
        [&](const std_msgs::Empty::ConstPtr&) { recorder_ready = true; });
  }
  while (ros::ok()) {
    bool outputs_ready = recorder_ready;
    if (options_.wait_for_subscribers)
      for (ros::Publisher* p : outputs)
        outputs_ready = outputs_ready && (!*p || p->getNumSubscribers() > 0);
    // Lockstep: the controller must hear the t = 0 IMU sample and be heard answering it.
    const bool controller_ready = !options_.lockstep || (imu_pub_.getNumSubscribers() > 0 &&
                                                         motor_sub_.getNumPublishers() > 0);
    if (outputs_ready && controller_ready) return true;
    if (ros::WallTime::now() > give_up) {
      if (!outputs_ready)
        ROS_WARN("flagella_sim: %s after %.1f s; starting",
                 recorder_ready ? "not every output topic has a subscriber"
                                : ("no message on " + options_.wait_for_recorder).c_str(),
                 options_.wait_timeout);
      if (!controller_ready)
        ROS_WARN(
            "flagella_sim: lockstep: no imu subscriber and motor_command publisher after "
            "%.1f s; starting",
            options_.wait_timeout);
      return true;
    }
    if (clock_pub_) {
      // rosbag and every other sim-time node treat t = 0 as "no clock yet": 1 ns lets them
      // start (and subscribe) before the first step.
      rosgraph_msgs::Clock c;
      c.clock = ros::Time(0, 1);
      clock_pub_.publish(c);
    }
    ros::spinOnce();
    sleepWall(kIdlePoll * 10);
  }
  return false;
}

bool SimNode::lockstepReady() {
  if (!awaiting_command_) return true;
  const flagella::CommandWait wait = lockstepGate(options_).commands(
      heard(motor_stamp_), heard(slider_stamp_), awaited_stamp_.toSec(),
      (ros::WallTime::now() - await_wall_start_).toSec());
  if (wait.verdict == flagella::CommandWait::Verdict::Waiting) {
    // Sleeps until a callback is queued (at most kLockstepPoll) and runs what is there.
    ros::getGlobalCallbackQueue()->callAvailable(ros::WallDuration(kLockstepPoll));
    return false;
  }
  if (wait.verdict == flagella::CommandWait::Verdict::TimedOut) {
    ++lockstep_timeouts_;
    ROS_WARN(
        "flagella_sim: lockstep: no %s stamped >= %.6f s within %.3f s of wall time; stepping "
        "on (the command failsafe applies)",
        wait.missing, awaited_stamp_.toSec(), wait.limit);
  }
  awaiting_command_ = false;
  return true;
}

bool SimNode::followersCaughtUp() {
  std::vector<flagella::FollowerClock> clocks;
  clocks.reserve(followers_.size());
  for (const auto& f : followers_) clocks.push_back({f->time, f->lost});
  const double waited =
      waiting_for_followers_ ? (ros::WallTime::now() - follower_wait_start_).toSec() : 0.0;
  const flagella::FollowerWait wait = lockstepGate(options_).followers(
      clocks, clockTime(), session_->dt(), waiting_for_followers_, waited);
  switch (wait.verdict) {
    case flagella::FollowerWait::Verdict::CaughtUp:
      waiting_for_followers_ = false;
      return true;
    case flagella::FollowerWait::Verdict::GiveUp:
      waiting_for_followers_ = false;  // the next wait starts afresh for the followers left
      for (const std::size_t i : wait.behind) {
        followers_[i]->lost = true;
        ROS_WARN(
            "flagella_sim: follower %s silent for %.1f wall s at t = %.3f s; no longer "
            "waiting for it",
            followers_[i]->name.c_str(), wait.limit, clockTime());
      }
      return true;
    case flagella::FollowerWait::Verdict::StartWaiting:
      waiting_for_followers_ = true;
      follower_wait_start_ = ros::WallTime::now();
      break;
    case flagella::FollowerWait::Verdict::Waiting:
      break;
  }
  ros::getGlobalCallbackQueue()->callAvailable(ros::WallDuration(kLockstepPoll));
  return false;
}

bool SimNode::readyToStep() {
  if (paused_ || session_->halted()) return false;
  if (!lockstepReady()) return false;
  if (!followersCaughtUp()) return false;
  if (!options_.publish_clock) return clockTime() + 0.5 * session_->dt() <= followed_clock_;
  if (options_.real_time_factor <= 0.0) return true;
  const double due_wall = (session_->time() - pace_sim_start_) / options_.real_time_factor;
  const double ahead = due_wall - (ros::WallTime::now() - pace_wall_start_).toSec();
  if (ahead <= 0.0) return true;
  sleepWall(std::min(ahead, kMaxPaceSleep));
  return false;
}

int SimNode::run() {
  if (!waitForSubscribers()) return 0;
  run_wall_start_ = pace_wall_start_ = last_progress_ = ros::WallTime::now();
  pace_sim_start_ = session_->time();
  publishOutputs(true);
  publishTime();
  publishDiagnostics();
  ros::WallTime last_wall_diagnostics = ros::WallTime::now();
  while (ros::ok()) {
    ros::spinOnce();
    if (options_.duration > 0.0 && clockTime() >= options_.duration - 0.5 * session_->dt()) break;
    if (!readyToStep()) {
      if ((paused_ || session_->halted() || !options_.publish_clock || awaiting_command_) &&
          (ros::WallTime::now() - last_wall_diagnostics).toSec() > kWallDiagnosticsPeriod) {
        publishDiagnostics();
        last_wall_diagnostics = ros::WallTime::now();
      }
      if (paused_ || session_->halted()) sleepWall(kIdlePoll);
      continue;
    }
    const bool stepped = session_->step();
    logFailsafeChange();
    if (!stepped && !was_halted_) {
      was_halted_ = true;
      ROS_ERROR_STREAM("flagella_sim: " << session_->health().message);
      publishDiagnostics();
      continue;
    }
    if (clock_pub_) {
      rosgraph_msgs::Clock c;
      c.clock = stamp();
      clock_pub_.publish(c);
    }
    publishOutputs(false);
    publishTime();
    if (schedule_.diagnosticsDue(session_->time())) publishDiagnostics();
    logProgress();
  }
  publishDiagnostics();
  printSummary();
  sleepWall(kDrainTime);
  return 0;
}

}  // namespace flagella::sim_node
