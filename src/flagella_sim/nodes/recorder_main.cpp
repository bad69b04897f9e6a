// flagella_record: a bag recorder that drops nothing. rosbag record subscribes with a queue of 100
// messages and stops at SIGINT with its queue unwritten, so a session run as fast as possible
// (thousands of messages per wall second) loses a fifth of its IMU samples. This one subscribes
// with unbounded queues, writes every message it has received before it closes the bag at
// SIGINT, and announces on the latched topic ~ready (std_msgs/Empty) when it is connected to
// every topic named exactly, so a simulator can hold t = 0 until then (sim param
// wait_for_recorder).
//
//   flagella_record --output-name BAG [--lz4] [--all] [--exclude REGEX] [--regex PATTERN]...
//                   [TOPIC ...]
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <rosbag/bag.h>
#include <std_msgs/Empty.h>
#include <topic_tools/shape_shifter.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <map>
#include <regex>
#include <set>
#include <string>
#include <vector>

namespace {

std::atomic<bool> g_stop{false};
void onSignal(int) { g_stop = true; }

constexpr double kDiscoveryPeriod = 0.25;  // [s wall] between looks at the master's topic list
constexpr double kDrainLimit = 30.0;       // [s wall] to write what is queued after SIGINT

struct RecorderOptions {
  std::string output;
  bool lz4 = false, all = false;
  std::vector<std::string> topics;  // exact names
  std::vector<std::regex> patterns, excludes;
};

int usage(const char* error) {
  if (error) std::fprintf(stderr, "flagella_record: %s\n", error);
  std::fprintf(error ? stderr : stdout,
               "usage: flagella_record --output-name BAG [--lz4] [--all] [--exclude REGEX] "
               "[--regex PATTERN]... [TOPIC ...]\n"
               "Records the named topics, the topics matching a PATTERN, or with --all every "
               "topic (minus --exclude) to BAG, dropping nothing; publishes ~ready (latched) once "
               "connected to every TOPIC named.\n");
  return error ? 2 : 0;
}

bool parse(const std::vector<std::string>& args, RecorderOptions& o, std::string& error) {
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    const auto value = [&](const std::string& flag) -> std::string {
      if (a.rfind(flag + "=", 0) == 0) return a.substr(flag.size() + 1);
      if (a == flag && i + 1 < args.size()) return args[++i];
      error = flag + " needs a value";
      return "";
    };
    try {
      if (a == "--lz4")
        o.lz4 = true;
      else if (a == "--all")
        o.all = true;
      else if (a.rfind("--output-name", 0) == 0)
        o.output = value("--output-name");
      else if (a.rfind("--exclude", 0) == 0)
        o.excludes.emplace_back(value("--exclude"));
      else if (a.rfind("--regex", 0) == 0)
        o.patterns.emplace_back(value("--regex"));
      else if (a.rfind("-", 0) == 0)
        error = "unknown option '" + a + "'";
      else
        o.topics.push_back(ros::names::resolve(a));
    } catch (const std::regex_error& e) {
      error = "bad regular expression in '" + a + "': " + e.what();
    }
    if (!error.empty()) return false;
  }
  if (o.output.empty())
    error = "--output-name BAG is required";
  else if (!o.all && o.topics.empty() && o.patterns.empty())
    error = "no topics to record";
  return error.empty();
}

class Recorder {
 public:
  explicit Recorder(RecorderOptions options) : o_(std::move(options)) {
    const std::string partial = o_.output + ".active";
    bag_.open(partial, rosbag::bagmode::Write);
    if (o_.lz4) bag_.setCompression(rosbag::compression::LZ4);
    ros::NodeHandle pnh("~");
    ready_pub_ = pnh.advertise<std_msgs::Empty>("ready", 1, /*latch=*/true);
  }

  /// Subscribes to the topics that appeared since the last look; announces ~ready once.
  void discover() {
    ros::master::V_TopicInfo infos;
    if (!ros::master::getTopics(infos)) return;
    for (const auto& info : infos)
      if (!subscribers_.count(info.name) && wanted(info.name)) subscribe(info.name);
    if (!ready_ && !o_.topics.empty() && connectedToAllNamed()) {
      ready_ = true;
      ready_pub_.publish(std_msgs::Empty());
      ROS_INFO("flagella_record: connected to all %zu named topics; recording to %s",
               o_.topics.size(), o_.output.c_str());
    }
  }

  /// Closes the bag under its final name and prints the messages written per topic.
  void close() {
    subscribers_.clear();
    bag_.close();
    std::rename((o_.output + ".active").c_str(), o_.output.c_str());
    long total = 0;
    std::string line;
    for (const auto& [topic, count] : written_) {
      total += count;
      line += " " + topic + "=" + std::to_string(count);
    }
    ROS_INFO("flagella_record: %ld messages written to %s:%s", total, o_.output.c_str(),
             line.c_str());
  }

 private:
  bool wanted(const std::string& topic) const {
    for (const auto& e : o_.excludes)
      if (std::regex_match(topic, e)) return false;
    if (o_.all) return true;
    for (const auto& t : o_.topics)
      if (t == topic) return true;
    for (const auto& p : o_.patterns)
      if (std::regex_match(topic, p)) return true;
    return false;
  }

  bool connectedToAllNamed() const {
    for (const auto& t : o_.topics) {
      const auto it = subscribers_.find(t);
      if (it == subscribers_.end() || it->second.getNumPublishers() == 0) return false;
    }
    return true;
  }

  void subscribe(const std::string& topic) {
    ros::SubscribeOptions ops;
    // queue 0: unbounded (a message is dropped only if this process runs out of memory)
    ops.initByFullCallbackType<const ros::MessageEvent<topic_tools::ShapeShifter const>&>(
        topic, 0, [this, topic](const ros::MessageEvent<topic_tools::ShapeShifter const>& e) {
          write(topic, e);
        });
    ops.transport_hints = ros::TransportHints().tcpNoDelay();
    subscribers_[topic] = nh_.subscribe(ops);
  }

  void write(const std::string& topic,
             const ros::MessageEvent<topic_tools::ShapeShifter const>& event) {
    ros::Time t = ros::Time::now();
    if (t < ros::TIME_MIN) t = ros::TIME_MIN;  // simulated time 0: a bag needs t > 0
    bag_.write(topic, t, *event.getConstMessage(), event.getConnectionHeaderPtr());
    ++written_[topic];
  }

  RecorderOptions o_;
  ros::NodeHandle nh_;
  rosbag::Bag bag_;
  ros::Publisher ready_pub_;
  std::map<std::string, ros::Subscriber> subscribers_;
  std::map<std::string, long> written_;
  bool ready_ = false;
};

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "flagella_record", ros::init_options::NoSigintHandler);
  std::vector<std::string> args;
  ros::removeROSArgs(argc, argv, args);
  args.erase(args.begin());
  for (const auto& a : args)
    if (a == "-h" || a == "--help") return usage(nullptr);
  RecorderOptions options;
  std::string error;
  if (!parse(args, options, error)) return usage(error.c_str());
  std::signal(SIGINT, onSignal);
  std::signal(SIGTERM, onSignal);
  try {
    Recorder recorder(options);
    ros::CallbackQueue* queue = ros::getGlobalCallbackQueue();
    ros::WallTime next_look = ros::WallTime::now();
    while (!g_stop && ros::ok()) {
      if (ros::WallTime::now() >= next_look) {
        recorder.discover();
        next_look = ros::WallTime::now() + ros::WallDuration(kDiscoveryPeriod);
      }
      queue->callAvailable(ros::WallDuration(0.02));
    }
    // Write everything already received before closing the bag.
    const ros::WallTime give_up = ros::WallTime::now() + ros::WallDuration(kDrainLimit);
    while (!queue->isEmpty() && ros::WallTime::now() < give_up)
      queue->callAvailable(ros::WallDuration(0.0));
    recorder.close();
  } catch (const std::exception& e) {
    ROS_FATAL("flagella_record: %s", e.what());
    return 1;
  }
  ros::shutdown();
  return 0;
}
