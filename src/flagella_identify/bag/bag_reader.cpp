#include "flagella_identify/bag_reader.h"

#include <flagella_msgs/RodState.h>
#include <geometry_msgs/PointStamped.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

#include "flagella_sim/core/units.h"

namespace flagella {
namespace identify {

namespace {

constexpr double kTwoPi = 2.0 * units::pi;  // [rad] per turn
constexpr size_t kMinSamples = 3;

/// "/ns/leaf" with a single leading slash and no trailing one in the namespace.
std::string topicName(const std::string& ns, const std::string& leaf) {
  std::string prefix = ns;
  while (!prefix.empty() && prefix.back() == '/') prefix.pop_back();
  if (!prefix.empty() && prefix.front() != '/') prefix = "/" + prefix;
  return prefix + "/" + leaf;
}

std::string withLeadingSlash(const std::string& topic) {
  return !topic.empty() && topic.front() == '/' ? topic : "/" + topic;
}

struct Topic {
  std::string recorded;  ///< as in the bag (for the query)
  std::string name;      ///< with a leading slash (for messages)
};

struct RodSample {
  double stamp = 0.0;
  Vec3 position = Vec3::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  double head_angle = 0.0;
  double tail_angle = 0.0;
  double omega_motor = 0.0;
};

class BagFile {
 public:
  BagFile(const std::string& path, const std::string& ns) : path_(path), ns_(ns) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
      throw DataError(path, 0, 0, "cannot open the bag (no such file)");
    try {
      bag_.open(path, rosbag::bagmode::Read);
    } catch (const rosbag::BagException& e) {
      throw DataError(path, 0, 0, std::string("cannot read the bag: ") + e.what());
    }
    rosbag::View all(bag_);
    if (all.size() == 0) throw DataError(path, 0, 0, "the bag holds no messages");
    for (const rosbag::ConnectionInfo* c : all.getConnections())
      topics_[withLeadingSlash(c->topic)] = {c->topic, c->datatype};
  }

  /// `leaf` in the namespace (its recorded name and the name for messages); throws naming the
  /// topic if absent or of another type.
  Topic topic(const std::string& leaf, const std::string& type) const {
    const std::string name = topicName(ns_, leaf);
    const auto it = topics_.find(name);
    if (it == topics_.end()) {
      std::string present;
      for (const auto& [t, info] : topics_) present += (present.empty() ? "" : ", ") + t;
      throw DataError(
          path_, 0, 0,
          "topic '" + name + "' (" + type + ") not found (topics in the bag: " + present + ")");
    }
    if (it->second.second != type)
      throw DataError(path_, 0, 0,
                      "topic '" + name + "' has type " + it->second.second + ", expected " + type);
    return {it->second.first, name};
  }

  rosbag::Bag& bag() { return bag_; }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::string ns_;
  rosbag::Bag bag_;
  std::map<std::string, std::pair<std::string, std::string>> topics_;  // name -> recorded, type
};

/// Appends `stamp` unless it repeats the last one; throws if time goes backwards.
bool acceptStamp(const std::vector<double>& stamps, double stamp, const std::string& path,
                 const std::string& topic, size_t message) {
  if (stamps.empty() || stamp > stamps.back()) return true;
  if (stamp == stamps.back()) return false;
  throw DataError(path, 0, 0,
                  "topic '" + topic + "': header stamp " + std::to_string(stamp) +
                      " s of message " + std::to_string(message + 1) +
                      " is earlier than the previous one (" + std::to_string(stamps.back()) +
                      " s); was the simulation reset during the recording?");
}

std::vector<RodSample> readRodStates(BagFile& file) {
  const Topic rod_state = file.topic("rod_state", "flagella_msgs/RodState");
  const std::string& topic = rod_state.name;
  std::vector<RodSample> samples;
  std::vector<double> stamps;
  rosbag::View view(file.bag(), rosbag::TopicQuery(rod_state.recorded));
  size_t index = 0;
  for (const rosbag::MessageInstance& m : view) {
    const flagella_msgs::RodState::ConstPtr msg = m.instantiate<flagella_msgs::RodState>();
    if (!msg)
      throw DataError(file.path(), 0, 0,
                      "topic '" + topic + "': message " + std::to_string(index + 1) +
                          " is not a flagella_msgs/RodState");
    const double stamp = msg->header.stamp.toSec();
    if (acceptStamp(stamps, stamp, file.path(), topic, index)) {
      RodSample s;
      s.stamp = stamp;
      const auto& p = msg->head_pose.position;
      const auto& q = msg->head_pose.orientation;
      s.position = Vec3(p.x, p.y, p.z);
      s.orientation = Eigen::Quaterniond(q.w, q.x, q.y, q.z);
      const double norm = s.orientation.norm();
      if (!(norm > 1e-12) || !std::isfinite(norm))
        throw DataError(file.path(), 0, 0,
                        "topic '" + topic + "': message " + std::to_string(index + 1) +
                            " has a head_pose orientation of zero or non-finite norm");
      s.orientation.coeffs() /= norm;
      s.head_angle = msg->head_angle;
      s.tail_angle = msg->tail_angle;
      s.omega_motor = msg->omega_motor;
      if (!s.position.allFinite() || !std::isfinite(s.head_angle) || !std::isfinite(s.tail_angle) ||
          !std::isfinite(s.omega_motor))
        throw DataError(file.path(), 0, 0,
                        "topic '" + topic + "': message " + std::to_string(index + 1) +
                            " holds non-finite values");
      stamps.push_back(stamp);
      samples.push_back(s);
    }
    ++index;
  }
  if (samples.size() < kMinSamples)
    throw DataError(file.path(), 0, 0,
                    "topic '" + topic + "': a time series needs at least " +
                        std::to_string(kMinSamples) + " samples with distinct stamps, got " +
                        std::to_string(samples.size()));
  return samples;
}

struct Fix {
  double stamp;
  Vec3 position;
};

std::vector<Fix> readCameraFixes(BagFile& file, double first, double last) {
  const Topic camera_fix = file.topic("camera_fix", "geometry_msgs/PointStamped");
  const std::string& topic = camera_fix.name;
  std::vector<Fix> fixes;
  std::vector<double> stamps;
  rosbag::View view(file.bag(), rosbag::TopicQuery(camera_fix.recorded));
  size_t index = 0;
  for (const rosbag::MessageInstance& m : view) {
    const geometry_msgs::PointStamped::ConstPtr msg = m.instantiate<geometry_msgs::PointStamped>();
    if (!msg)
      throw DataError(file.path(), 0, 0,
                      "topic '" + topic + "': message " + std::to_string(index + 1) +
                          " is not a geometry_msgs/PointStamped");
    const double stamp = msg->header.stamp.toSec();
    const Vec3 p(msg->point.x, msg->point.y, msg->point.z);
    // Only fixes inside the rod_state span: the other signals are not extrapolated.
    if (stamp >= first && stamp <= last && p.allFinite() &&
        acceptStamp(stamps, stamp, file.path(), topic, index)) {
      stamps.push_back(stamp);
      fixes.push_back({stamp, p});
    }
    ++index;
  }
  if (fixes.size() < kMinSamples)
    throw DataError(file.path(), 0, 0,
                    "topic '" + topic + "': a time series needs at least " +
                        std::to_string(kMinSamples) +
                        " finite fixes with distinct stamps inside the rod_state time span, got " +
                        std::to_string(fixes.size()));
  return fixes;
}

}  // namespace

TimeSeries readTimeSeriesFromBag(const std::string& bag_path, const BagOptions& options) {
  try {
    BagFile file(bag_path, options.topic_namespace);
    const std::vector<RodSample> rod = readRodStates(file);
    const RodSample& first = rod.front();
    TimeSeries s;
    s.source = bag_path;
    s.has_z = true;
    const auto add = [&](double t, const Vec3& position, const Eigen::Quaterniond& q,
                         double head_angle, double tail_angle, double omega) {
      s.t.push_back(t);
      s.position.push_back(position);
      s.orientation.push_back(q);
      s.head_turns.push_back((head_angle - first.head_angle) / kTwoPi);
      s.tail_turns.push_back((tail_angle - first.tail_angle) / kTwoPi);
      s.omega_cmd.push_back(omega);
    };
    if (options.position == BagOptions::Position::kRodState) {
      for (const RodSample& r : rod)
        add(r.stamp - first.stamp, r.position, r.orientation, r.head_angle, r.tail_angle,
            r.omega_motor);
      return s;
    }
    const std::vector<Fix> fixes = readCameraFixes(file, first.stamp, rod.back().stamp);
    size_t k = 0;  // rod[k].stamp <= fix stamp < rod[k + 1].stamp
    for (const Fix& f : fixes) {
      while (k + 1 < rod.size() && rod[k + 1].stamp <= f.stamp) ++k;
      const RodSample& a = rod[k];
      const RodSample& b = k + 1 < rod.size() ? rod[k + 1] : rod[k];
      const double alpha = b.stamp > a.stamp ? (f.stamp - a.stamp) / (b.stamp - a.stamp) : 0.0;
      add(f.stamp - fixes.front().stamp, f.position, a.orientation.slerp(alpha, b.orientation),
          a.head_angle + alpha * (b.head_angle - a.head_angle),
          a.tail_angle + alpha * (b.tail_angle - a.tail_angle), a.omega_motor);
    }
    return s;
  } catch (const DataError&) {
    throw;
  } catch (const std::exception& e) {  // rosbag::BagException, ros::Exception (deserialising)
    throw DataError(bag_path, 0, 0, std::string("cannot read the bag: ") + e.what());
  }
}

void enableBagInput() { registerBagReader(&readTimeSeriesFromBag); }

}  // namespace identify
}  // namespace flagella
