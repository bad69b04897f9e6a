// flagella_sim_node: simulates one robot and publishes it to ROS (see sim_node.h).
#include <ros/ros.h>

#include <exception>

#include "flagella_sim/core/parameter_set.h"
#include "sim_node.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "flagella_sim");
  ros::NodeHandle nh;
  ros::NodeHandle private_nh("~");
  try {
    flagella::sim_node::SimNode node(nh, private_nh);
    return node.run();
  } catch (const flagella::ConfigError& e) {
    ROS_FATAL_STREAM("flagella_sim: configuration error: " << e.what());
    return 2;
  } catch (const std::exception& e) {
    ROS_FATAL_STREAM("flagella_sim: " << e.what());
    return 1;
  }
}
