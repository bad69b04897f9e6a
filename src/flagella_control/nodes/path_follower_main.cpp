#include <ros/ros.h>

#include <exception>

#include "path_follower_node.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "flagella_path_follower");
  ros::NodeHandle nh, pnh("~");
  try {
    flagella::control::node::PathFollowerNode node(nh, pnh);
    ros::spin();
    return node.exitCode();
  } catch (const std::exception& e) {
    ROS_FATAL("flagella_path_follower: %s", e.what());
    return 1;
  }
}
