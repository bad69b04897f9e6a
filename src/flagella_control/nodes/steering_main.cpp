// flagella_steering_controller: the mass-transformer closed loop (docs/model.md 7.4) as a ROS
// node; see steering_node.h.
#include <ros/ros.h>

#include <exception>

#include "steering_node.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "flagella_steering_controller");
  ros::NodeHandle nh, pnh("~");
  try {
    flagella::control::node::SteeringNode node(nh, pnh);
    ros::spin();
    return node.exitCode();
  } catch (const std::exception& e) {
    ROS_FATAL("flagella_steering_controller: %s", e.what());
    return 1;
  }
}
