#include "sim_node.h"

#include <diagnostic_msgs/DiagnosticArray.h>
#include <flagella_msgs/RodState.h>
#include <flagella_msgs/lcm_conversions.h>
#include <geometry_msgs/PointStamped.h>
#include <ros/callback_queue.h>
#include <sensor_msgs/Imu.h>
#include <std_msgs/Empty.h>
#include <tf2_msgs/TFMessage.h>
#include <visualization_msgs/MarkerArray.h>

#include <sstream>

#include "flagella_sim/core/file_paths.h"
#include "flagella_sim/lcm_io/lcm_messages.h"
#include "flagella_sim/simulation/simulation_config.h"
#include "node_params.h"

namespace flagella::sim_node {

namespace {
constexpr double kMaxRate = 1e4;  // [Hz]
constexpr double kMaxRealTimeFactor = 1e6;
constexpr double kMaxDuration = 1e9;     // [s]
constexpr double kIdlePoll = 0.005;      // [s wall] poll period while paused or waiting
constexpr double kMaxPaceSleep = 0.002;  // [s wall] longest sleep while pacing
constexpr double kDrainTime = 1.0;       // [s wall] let subscribers receive the last messages
constexpr double kWallDiagnosticsPeriod = 1.0;  // [s wall] diagnostics while paused or halted
constexpr double kLockstepPoll = 0.001;         // [s wall] longest wait for a callback in lockstep
constexpr double kMaxLockstepTimeout = 1e6;     // [s wall]
// Outgoing queue per subscriber: deep enough that a recorder keeps up with a session running
// many times faster than real time (100 Hz IMU at 30x is 3000 messages per second).
constexpr int kQueue = 5000;

std::string defaultPrefix(const ros::NodeHandle& nh) {
  std::string ns = nh.getNamespace();
  while (!ns.empty() && ns.front() == '/') ns.erase(ns.begin());
  for (char& c : ns)
    if (c == '/') c = '_';
  return ns.empty() ? "flagella" : ns;
}

SimNodeOptions nodeOptionsFromParams(const ros::NodeHandle& nh, const ros::NodeHandle& pnh) {
  SimNodeOptions o;
  if (!pnh.getParam("config", o.config_path) || o.config_path.empty())
    throw flagella::ConfigError("parameter ~config (path of a robot config YAML) is required");
  // a relative path: from the directory roslaunch was started in (the launch files' base_directory)
  o.config_path =
      flagella::resolveAgainst(o.config_path, pnh.param<std::string>("base_directory", ""));
  pnh.param<std::string>("world_frame", o.world_frame, o.world_frame);
  pnh.param<std::string>("tf_prefix", o.tf_prefix, defaultPrefix(nh));
  o.real_time_factor = rangedParam(pnh, "real_time_factor", o.real_time_factor, 0.0,
                                   kMaxRealTimeFactor, "(0: as fast as possible)");
  pnh.param("publish_clock", o.publish_clock, o.publish_clock);
  o.state_rate = rangedParam(pnh, "state_rate", o.state_rate, 1e-3, kMaxRate, "Hz");
  o.marker_rate = rangedParam(pnh, "marker_rate", o.marker_rate, 1e-3, kMaxRate, "Hz");
  o.path_rate = rangedParam(pnh, "path_rate", o.path_rate, 1e-3, kMaxRate, "Hz");
  o.diagnostics_rate =
      rangedParam(pnh, "diagnostics_rate", o.diagnostics_rate, 1e-3, kMaxRate, "Hz");
  o.path_max_poses =
      static_cast<int>(rangedParam(pnh, "path_max_poses", o.path_max_poses, 1, 1e7, "poses"));
  o.duration = rangedParam(pnh, "duration", o.duration, 0.0, kMaxDuration, "s (0: forever)");
  pnh.param("wait_for_subscribers", o.wait_for_subscribers, o.wait_for_subscribers);
  pnh.param<std::string>("wait_for_recorder", o.wait_for_recorder, o.wait_for_recorder);
  std::string followers;
  pnh.param<std::string>("followers", followers, "");
  std::istringstream names(followers);
  for (std::string name; names >> name;) o.followers.push_back(name);
  o.wait_timeout = rangedParam(pnh, "wait_timeout", o.wait_timeout, 0.0, 1e6, "s");
  o.progress_period =
      rangedParam(pnh, "progress_period", o.progress_period, 0.0, 1e6, "wall s (0: none)");
  pnh.param("lockstep", o.lockstep, o.lockstep);
  pnh.param("lockstep_slider", o.lockstep_slider, o.lockstep_slider);
  o.lockstep_timeout = rangedParam(pnh, "lockstep_timeout", o.lockstep_timeout, 1e-3,
                                   kMaxLockstepTimeout, "s of wall time");
  o.markers.tail_width =
      rangedParam(pnh, "marker_tail_width", o.markers.tail_width, 1e-5, 1.0, "m");
  o.markers.head_width =
      rangedParam(pnh, "marker_head_width", o.markers.head_width, 1e-5, 1.0, "m");
  return o;
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
                  << config.robot_name << " from " << options_.config_path << ", " << net.numNodes()
                  << " nodes, dt " << config.dt << " s, "
                  << (options_.real_time_factor > 0.0
                          ? std::to_string(options_.real_time_factor) + "x real time"
                          : std::string("as fast as possible"))
                  << (options_.publish_clock ? "" : ", following /clock")
                  << (options_.lockstep ? ", lockstep with motor_command" : ""));
}

template <typename M>
void SimNode::publish(ros::Publisher& pub, const M& msg) {
  pub.publish(msg);
  ++published_[pub.getTopic()];
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
  const bool motor_answered = motor_stamp_.answers(awaited_stamp_);
  const bool slider_answered = !options_.lockstep_slider || slider_stamp_.answers(awaited_stamp_);
  if (motor_answered && slider_answered) {
    awaiting_command_ = false;
    return true;
  }
  // A controller not heard from yet may still be starting up (planning a path, say): it gets
  // wait_timeout, one that stalls mid-run lockstep_timeout.
  const bool starting = !motor_stamp_.seen || (options_.lockstep_slider && !slider_stamp_.seen);
  const double limit = starting ? options_.wait_timeout : options_.lockstep_timeout;
  if ((ros::WallTime::now() - await_wall_start_).toSec() > limit) {
    ++lockstep_timeouts_;
    ROS_WARN(
        "flagella_sim: lockstep: no %s stamped >= %.6f s within %.3f s of wall time; stepping "
        "on (the command failsafe applies)",
        motor_answered ? "slider_command" : "motor_command", awaited_stamp_.toSec(), limit);
    awaiting_command_ = false;
    return true;
  }
  // Sleeps until a callback is queued (at most kLockstepPoll) and runs what is there.
  ros::getGlobalCallbackQueue()->callAvailable(ros::WallDuration(kLockstepPoll));
  return false;
}

bool SimNode::followersCaughtUp() {
  bool caught_up = true;
  for (const auto& f : followers_)
    caught_up = caught_up && (f->lost || f->time + 0.5 * session_->dt() >= clockTime());
  if (caught_up) {
    waiting_for_followers_ = false;
    return true;
  }
  // A follower still starting up (nothing heard yet) gets wait_timeout, one that stalls mid-run
  // lockstep_timeout; then it is warned about once and no longer waited for.
  bool starting = false;
  for (const auto& f : followers_) starting = starting || (!f->lost && f->time < 0.0);
  const double limit = starting ? options_.wait_timeout : options_.lockstep_timeout;
  if (!waiting_for_followers_) {
    waiting_for_followers_ = true;
    follower_wait_start_ = ros::WallTime::now();
  } else if ((ros::WallTime::now() - follower_wait_start_).toSec() > limit) {
    for (const auto& f : followers_)
      if (!f->lost && f->time + 0.5 * session_->dt() < clockTime()) {
        f->lost = true;
        ROS_WARN(
            "flagella_sim: follower %s silent for %.1f wall s at t = %.3f s; no longer "
            "waiting for it",
            f->name.c_str(), limit, clockTime());
      }
    return true;
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
