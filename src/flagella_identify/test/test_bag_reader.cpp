// Bags of the simulator node's topics -> time series. The bags are written here with
// rosbag::Bag from messages built in the test (no roscore needed).
#include <flagella_msgs/MotorCommand.h>
#include <flagella_msgs/RodState.h>
#include <geometry_msgs/PointStamped.h>
#include <gtest/gtest.h>
#include <rosbag/bag.h>

#include <cmath>
#include <string>

#include "../../flagella_sim/test/support/temp_dir.h"
#include "flagella_identify/bag_reader.h"
#include "flagella_identify/data_io.h"
#include "flagella_sim/core/units.h"

namespace flagella::identify {
namespace {

using flagella::testing::errorMessageOf;
using flagella::testing::TempDir;

constexpr double kT0 = 100.0;  // first stamp [s]
constexpr double kDt = 0.1;

::testing::AssertionResult startsWith(const std::string& message, const std::string& prefix) {
  if (message.compare(0, prefix.size(), prefix) == 0) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << "message\n  " << message << "\ndoes not start with\n  " << prefix;
}

// Sample i of the synthetic run.
Vec3 positionOf(int i) { return Vec3(0.01 * i, 2e-3 + 1e-4 * i * i, -1e-3 * i); }
double headAngleOf(int i) { return 0.5 + units::pi * i; }        // half a turn per sample
double tailAngleOf(int i) { return 1.0 - 0.5 * units::pi * i; }  // a quarter turn back per sample
double omegaOf(int i) { return 3.0 + i; }
Eigen::Quaterniond orientationOf(int i) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(0.2 * i, Vec3::UnitZ()));
}

flagella_msgs::RodState rodState(double stamp, int i) {
  flagella_msgs::RodState msg;
  msg.header.stamp = ros::Time(stamp);
  msg.header.frame_id = "world";
  msg.robot_name = "robot_a";
  const Vec3 p = positionOf(i);
  msg.head_pose.position.x = p.x();
  msg.head_pose.position.y = p.y();
  msg.head_pose.position.z = p.z();
  const Eigen::Quaterniond q = orientationOf(i);
  msg.head_pose.orientation.w = 2.0 * q.w();  // not normalised: the reader normalises
  msg.head_pose.orientation.x = 2.0 * q.x();
  msg.head_pose.orientation.y = 2.0 * q.y();
  msg.head_pose.orientation.z = 2.0 * q.z();
  msg.head_angle = headAngleOf(i);
  msg.tail_angle = tailAngleOf(i);
  msg.omega_motor = omegaOf(i);
  msg.omega_h = 0.7;
  msg.omega_t = -0.3;
  return msg;
}

geometry_msgs::PointStamped fix(double stamp, const Vec3& p) {
  geometry_msgs::PointStamped msg;
  msg.header.stamp = ros::Time(stamp);
  msg.header.frame_id = "world";
  msg.point.x = p.x();
  msg.point.y = p.y();
  msg.point.z = p.z();
  return msg;
}

/// A bag like a recording of two simulator nodes: /robot_a with 5 rod states (one repeated),
/// camera fixes and motor commands, /robot_b with rod states of another run.
std::string writeRunBag(const TempDir& dir) {
  const std::string path = (dir.path() / "run.bag").string();
  rosbag::Bag bag(path, rosbag::bagmode::Write);
  for (int i = 0; i < 5; ++i) {
    const double stamp = kT0 + kDt * i;
    flagella_msgs::MotorCommand command;
    command.header.stamp = ros::Time(stamp);
    command.omega = 99.0;
    bag.write("/robot_a/motor_command", ros::Time(stamp), command);
    bag.write("/robot_a/rod_state", ros::Time(stamp), rodState(stamp, i));
    if (i == 2)  // published twice at the same instant: kept once
      bag.write("/robot_a/rod_state", ros::Time(stamp), rodState(stamp, i));
    flagella_msgs::RodState other = rodState(stamp + 0.01, 10 + i);
    bag.write("/robot_b/rod_state", ros::Time(stamp), other);
  }
  // Fixes: one before the first rod state and one after the last are dropped.
  bag.write("/robot_a/camera_fix", ros::Time(kT0), fix(kT0 - 0.05, Vec3(9, 9, 9)));
  for (int k = 0; k < 3; ++k) {
    const double stamp = kT0 + 0.05 + 0.1 * k;
    bag.write("/robot_a/camera_fix", ros::Time(stamp), fix(stamp, Vec3(1e-3 * k, 2e-3, 0.0)));
  }
  bag.write("/robot_a/camera_fix", ros::Time(kT0 + 1.0), fix(kT0 + 1.0, Vec3(9, 9, 9)));
  bag.close();
  return path;
}

TEST(BagReader, RodStateGivesTheTrueHeadPose) {
  TempDir dir;
  const std::string path = writeRunBag(dir);
  BagOptions options;
  options.topic_namespace = "/robot_a";
  const TimeSeries s = readTimeSeriesFromBag(path, options);
  EXPECT_EQ(s.source, path);
  EXPECT_TRUE(s.has_z);
  ASSERT_EQ(s.t.size(), 5u);
  ASSERT_EQ(s.position.size(), 5u);
  ASSERT_EQ(s.orientation.size(), 5u);
  ASSERT_EQ(s.head_turns.size(), 5u);
  ASSERT_EQ(s.tail_turns.size(), 5u);
  ASSERT_EQ(s.omega_cmd.size(), 5u);
  for (int i = 0; i < 5; ++i) {
    SCOPED_TRACE(i);
    EXPECT_NEAR(s.t[i], kDt * i, 1e-6);  // ros::Time keeps nanoseconds
    EXPECT_NEAR((s.position[i] - positionOf(i)).norm(), 0.0, 1e-15);
    EXPECT_NEAR(s.orientation[i].norm(), 1.0, 1e-14);
    EXPECT_LT(s.orientation[i].angularDistance(orientationOf(i)), 1e-12);
    EXPECT_NEAR(s.head_turns[i], 0.5 * i, 1e-12);
    EXPECT_NEAR(s.tail_turns[i], -0.25 * i, 1e-12);
    EXPECT_DOUBLE_EQ(s.omega_cmd[i], omegaOf(i));  // from omega_motor, not motor_command
  }
  // The namespace without a leading slash (or with a trailing one) names the same topics.
  options.topic_namespace = "robot_b/";
  const TimeSeries b = readTimeSeriesFromBag(path, options);
  ASSERT_EQ(b.t.size(), 5u);
  EXPECT_NEAR((b.position[0] - positionOf(10)).norm(), 0.0, 1e-15);
  EXPECT_NEAR(b.head_turns[4], 0.5 * 4, 1e-12);  // relative to the first sample
}

TEST(BagReader, CameraFixesWithInterpolatedSignals) {
  TempDir dir;
  const std::string path = writeRunBag(dir);
  BagOptions options;
  options.topic_namespace = "/robot_a";
  options.position = BagOptions::Position::kCameraFix;
  const TimeSeries s = readTimeSeriesFromBag(path, options);
  ASSERT_EQ(s.t.size(), 3u);  // the fixes outside the rod_state span are dropped
  for (int k = 0; k < 3; ++k) {
    SCOPED_TRACE(k);
    EXPECT_NEAR(s.t[k], 0.1 * k, 1e-6);
    EXPECT_NEAR((s.position[k] - Vec3(1e-3 * k, 2e-3, 0.0)).norm(), 0.0, 1e-15);
    // Half-way between rod states k and k + 1.
    EXPECT_NEAR(s.head_turns[k], 0.5 * k + 0.25, 1e-6);
    EXPECT_NEAR(s.tail_turns[k], -0.25 * k - 0.125, 1e-6);
    EXPECT_LT(s.orientation[k].angularDistance(
                  Eigen::Quaterniond(Eigen::AngleAxisd(0.2 * k + 0.1, Vec3::UnitZ()))),
              1e-6);
    EXPECT_DOUBLE_EQ(s.omega_cmd[k], omegaOf(k));  // held from the rod state before
  }
}

TEST(BagReader, MetadataWithBagGoesThroughTheRegisteredReader) {
  enableBagInput();
  ASSERT_TRUE(bagReaderRegistered());
  TempDir dir;
  writeRunBag(dir);
  const std::string yaml =
      dir.write("run.yaml",
                "kind: time_series\n"
                "bag: run.bag\n"
                "description: tank run\n"
                "session_time_s: 30\n"
                "bag_namespace: /robot_a\n"
                "bag_position: camera_fix\n"
                "overrides: {robot.n_tails: 2}\n"
                "noise: {position_mm: 0.3, orientation_rad: 0.01, turns: 0.25}\n");
  const MeasuredData data = readMeasuredData(yaml);
  ASSERT_EQ(data.series.size(), 1u);
  const TimeSeries& s = data.series[0];
  EXPECT_EQ(s.source, yaml);
  EXPECT_EQ(s.description, "tank run");
  EXPECT_DOUBLE_EQ(s.session_time, 30.0);
  EXPECT_EQ(s.overrides, (std::vector<ConfigOverride>{{"robot.n_tails", "2"}}));
  EXPECT_DOUBLE_EQ(s.position_noise, 3e-4);
  EXPECT_DOUBLE_EQ(s.orientation_noise, 0.01);
  EXPECT_DOUBLE_EQ(s.turns_noise, 0.25);
  EXPECT_EQ(s.t.size(), 3u);  // camera fixes

  // The bag holds orientations and turns: their noise is required.
  const std::string no_turns = dir.write("n.yaml",
                                         "kind: time_series\n"
                                         "bag: run.bag\n"
                                         "bag_namespace: /robot_a\n"
                                         "noise: {position_mm: 0.3, orientation_rad: 0.01}\n");
  EXPECT_TRUE(startsWith(errorMessageOf<DataError>([&] { readMeasuredData(no_turns); }),
                         no_turns + ":4:1: noise.turns is required"));
  const std::string bad_position = dir.write("p.yaml",
                                             "kind: time_series\n"
                                             "bag: run.bag\n"
                                             "bag_position: imu\n"
                                             "noise: {position_mm: 0.3}\n");
  EXPECT_EQ(errorMessageOf<DataError>([&] { readMeasuredData(bad_position); }),
            bad_position + ":3:15: bag_position: expected rod_state or camera_fix, got 'imu'");
  const std::string missing = dir.write("m.yaml",
                                        "kind: time_series\n"
                                        "bag: nothere.bag\n"
                                        "noise: {position_mm: 0.3}\n");
  EXPECT_TRUE(startsWith(errorMessageOf<DataError>([&] { readMeasuredData(missing); }),
                         missing + ":2:6: bag: cannot open '"));
  registerBagReader({});
  EXPECT_FALSE(bagReaderRegistered());
}

TEST(BagReader, ErrorsNameTheBagAndTheTopic) {
  TempDir dir;
  const std::string path = writeRunBag(dir);
  const auto error = [](const std::string& bag, const BagOptions& options) {
    return errorMessageOf<DataError>([&] { readTimeSeriesFromBag(bag, options); });
  };
  BagOptions options;
  options.topic_namespace = "/robot_c";
  EXPECT_TRUE(startsWith(error(path, options),
                         path + ": topic '/robot_c/rod_state' (flagella_msgs/RodState) not found "
                                "(topics in the bag: /robot_a/camera_fix, "));
  options.topic_namespace = "/robot_b";
  options.position = BagOptions::Position::kCameraFix;
  EXPECT_TRUE(startsWith(error(path, options),
                         path + ": topic '/robot_b/camera_fix' (geometry_msgs/PointStamped) not "
                                "found"));

  const std::string missing = (dir.path() / "nothere.bag").string();
  EXPECT_EQ(error(missing, {}), missing + ": cannot open the bag (no such file)");

  const std::string text = dir.write("text.bag", "this is not a bag\n");
  EXPECT_TRUE(startsWith(error(text, {}), text + ": cannot read the bag: "));

  const std::string empty = (dir.path() / "empty.bag").string();
  { rosbag::Bag bag(empty, rosbag::bagmode::Write); }
  EXPECT_EQ(error(empty, {}), empty + ": the bag holds no messages");

  const std::string wrong_type = (dir.path() / "wrong.bag").string();
  {
    rosbag::Bag bag(wrong_type, rosbag::bagmode::Write);
    bag.write("/rod_state", ros::Time(kT0), fix(kT0, Vec3::Zero()));
  }
  EXPECT_EQ(error(wrong_type, {}), wrong_type +
                                       ": topic '/rod_state' has type "
                                       "geometry_msgs/PointStamped, expected "
                                       "flagella_msgs/RodState");

  const std::string backwards = (dir.path() / "backwards.bag").string();
  {
    rosbag::Bag bag(backwards, rosbag::bagmode::Write);
    bag.write("/rod_state", ros::Time(kT0), rodState(kT0 + 1.0, 0));
    bag.write("/rod_state", ros::Time(kT0 + 0.1), rodState(kT0 + 0.5, 1));  // reset
  }
  EXPECT_TRUE(startsWith(error(backwards, {}),
                         backwards + ": topic '/rod_state': header stamp 100.500000 s of message 2 "
                                     "is earlier than the previous one"));

  const std::string short_run = (dir.path() / "short.bag").string();
  {
    rosbag::Bag bag(short_run, rosbag::bagmode::Write);
    bag.write("rod_state", ros::Time(kT0), rodState(kT0, 0));  // recorded without the slash
    bag.write("rod_state", ros::Time(kT0 + 0.1), rodState(kT0 + 0.1, 1));
  }
  EXPECT_EQ(error(short_run, {}),
            short_run +
                ": topic '/rod_state': a time series needs at least 3 samples with "
                "distinct stamps, got 2");
}

}  // namespace
}  // namespace flagella::identify
