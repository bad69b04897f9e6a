// flagella_lcm_bridge: mirrors one robot's rod state, IMU and camera fix from ROS onto LCM, and
// LCM motor, slider and controller-status messages onto ROS, with the converters of flagella_msgs.
// Default provider: udpm with ttl=0 (never leaves the host). Tests use file:// or memq://.
#include <flagella_msgs/ControllerStatus.h>
#include <flagella_msgs/MotorCommand.h>
#include <flagella_msgs/RodState.h>
#include <flagella_msgs/SliderCommand.h>
#include <flagella_msgs/lcm_conversions.h>
#include <geometry_msgs/PointStamped.h>
#include <ros/ros.h>
#include <sensor_msgs/Imu.h>

#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <string>

#include "flagella_sim/lcm_io/lcm_messages.h"

namespace {

constexpr char kDefaultUrl[] = "udpm://239.255.76.67:7667?ttl=0";
constexpr int kQueue = 1000;
constexpr int kLcmPollMs = 2;  // LCM wait per loop turn; ROS callbacks run between turns

class LcmBridge {
 public:
  LcmBridge(ros::NodeHandle& nh, ros::NodeHandle& pnh) {
    std::string url, publish_url, subscribe_url, prefix;
    pnh.param<std::string>("lcm_url", url, kDefaultUrl);
    pnh.param<std::string>("lcm_publish_url", publish_url, url);
    pnh.param<std::string>("lcm_subscribe_url", subscribe_url, url);
    pnh.param<std::string>("channel_prefix", prefix, "FLAGELLA_");
    channels_ = flagella::LcmChannels::withPrefix(prefix);
    out_ = std::make_unique<lcm::LCM>(publish_url);
    in_ = subscribe_url == publish_url ? nullptr : std::make_unique<lcm::LCM>(subscribe_url);
    if (!out_->good() || (in_ && !in_->good()))
      throw std::runtime_error("cannot open LCM provider " + publish_url + " / " + subscribe_url);
    lcm::LCM& in = input();
    in.subscribe(channels_.motor_command, &LcmBridge::onMotor, this);
    in.subscribe(channels_.slider_command, &LcmBridge::onSlider, this);
    in.subscribe(channels_.controller_status, &LcmBridge::onStatus, this);
    motor_pub_ = nh.advertise<flagella_msgs::MotorCommand>("motor_command", kQueue);
    slider_pub_ = nh.advertise<flagella_msgs::SliderCommand>("slider_command", kQueue);
    status_pub_ = nh.advertise<flagella_msgs::ControllerStatus>("controller_status", kQueue);
    state_sub_ = nh.subscribe("rod_state", kQueue, &LcmBridge::onRodState, this);
    imu_sub_ = nh.subscribe("imu", kQueue, &LcmBridge::onImu, this);
    camera_sub_ = nh.subscribe("camera_fix", kQueue, &LcmBridge::onCameraFix, this);
    ROS_INFO_STREAM("flagella_lcm_bridge: ROS " << nh.getNamespace() << " <-> LCM " << prefix
                                                << "* (publish " << publish_url << ", subscribe "
                                                << subscribe_url << ")");
  }

  void spin() {
    while (ros::ok()) {
      ros::spinOnce();
      input().handleTimeout(kLcmPollMs);
    }
    ROS_INFO("flagella_lcm_bridge: %ld messages to LCM, %ld to ROS", to_lcm_, to_ros_);
  }

 private:
  lcm::LCM& input() { return in_ ? *in_ : *out_; }

  void onRodState(const flagella_msgs::RodState& msg) {
    const flagella_lcm::rod_state_t out = flagella_msgs::toLcm(msg);
    out_->publish(channels_.rod_state, &out);
    ++to_lcm_;
  }
  void onImu(const sensor_msgs::Imu& msg) {
    const flagella_lcm::imu_t out = flagella_msgs::toLcm(msg);
    out_->publish(channels_.imu, &out);
    ++to_lcm_;
  }
  void onCameraFix(const geometry_msgs::PointStamped& msg) {
    const flagella_lcm::point_stamped_t out = flagella_msgs::toLcm(msg);
    out_->publish(channels_.camera_fix, &out);
    ++to_lcm_;
  }
  void onMotor(const lcm::ReceiveBuffer*, const std::string&,
               const flagella_lcm::motor_command_t* msg) {
    motor_pub_.publish(flagella_msgs::toRos(*msg));  // the simulator validates the value
    ++to_ros_;
  }
  void onSlider(const lcm::ReceiveBuffer*, const std::string&,
                const flagella_lcm::slider_command_t* msg) {
    slider_pub_.publish(flagella_msgs::toRos(*msg));
    ++to_ros_;
  }
  void onStatus(const lcm::ReceiveBuffer*, const std::string&,
                const flagella_lcm::controller_status_t* msg) {
    status_pub_.publish(flagella_msgs::toRos(*msg));
    ++to_ros_;
  }

  flagella::LcmChannels channels_;
  std::unique_ptr<lcm::LCM> out_, in_;
  ros::Publisher motor_pub_, slider_pub_, status_pub_;
  ros::Subscriber state_sub_, imu_sub_, camera_sub_;
  long to_lcm_ = 0, to_ros_ = 0;
};

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "flagella_lcm_bridge");
  ros::NodeHandle nh;
  ros::NodeHandle pnh("~");
  try {
    LcmBridge bridge(nh, pnh);
    bridge.spin();
  } catch (const std::exception& e) {
    ROS_FATAL_STREAM("flagella_lcm_bridge: " << e.what());
    return 1;
  }
  return 0;
}
