// simulated_robot: a robot and its place recogniser from rrr simulate.
#include <ros/ros.h>

#include "simulated_robot.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "simulated_robot");
  ros::NodeHandle nh, private_nh("~");
  rrr_ros::SimulatedRobotOptions options;
  try {
    options = rrr_ros::SimulatedRobotOptions::Read(private_nh);
  } catch (const std::exception& e) {
    ROS_FATAL("simulated_robot: %s", e.what());
    return 1;
  }
  rrr_ros::SimulatedRobot robot(nh, private_nh, options);
  ros::spin();
  return 0;
}
