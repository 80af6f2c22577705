// A robot and its place recogniser, played from a simulated world.
#ifndef RRR_ROS_SIMULATED_ROBOT_H_
#define RRR_ROS_SIMULATED_ROBOT_H_

#include <ros/ros.h>

#include <string>
#include <vector>

#include "rrr/graph/odometry_chain.h"
#include "rrr/graph/odometry_noise.h"
#include "rrr/sim/simulated_world.h"

namespace rrr_ros {

struct SimulatedRobotOptions {
  rrr::WorldOptions world;  // poses, false_loops, group, seed, ...
  double rate = 20.0;       // odometry messages per second
  std::string odom_frame = "odom", base_frame = "base_link";
  // One robot of a fleet: the world's path cut into as many consecutive
  // parts as `robots` names, this robot (`robot`, one of them) driving its
  // part with its odometry from zero. Empty: the whole world, alone.
  std::vector<std::string> robots;
  std::string robot;
  // Its odometry starts again at zero at this pose of its part (a restart
  // of the robot mid-run); -1: never.
  int restart_at = -1;

  // Reads the private parameters (poses, false_loops, group, seed, rate,
  // odom_frame, base_frame, robots, robot, restart_at); throws
  // std::invalid_argument naming a bad one.
  static SimulatedRobotOptions Read(const ros::NodeHandle& nh);
};

// Publishes the world of rrr simulate as a robot and a place recogniser
// would: nav_msgs/Odometry on `odom` at `rate` (the pose in the odometry
// frame with its growing covariance), and each loop candidate, true or
// false, on `loop_closures` right after its later pose, naming its poses by
// time stamp. As one robot of a fleet, its part of the world, and each
// candidate whose later end (counted in each robot's part; a tie goes to the
// later robot) is its own on `fleet_loop_closures`, naming robot and
// keyframe id (every odometry message a keyframe) at both ends. Publishes
// std_msgs/Bool true on the latched `~done` after the last pose.
class SimulatedRobot {
 public:
  SimulatedRobot(ros::NodeHandle& nh, ros::NodeHandle& private_nh,
                 const SimulatedRobotOptions& options);

 private:
  void OnTimer(const ros::TimerEvent& event);
  // The robot of a fleet whose part holds world pose `p`.
  int RobotOf(int p) const;

  SimulatedRobotOptions options_;
  rrr::SimulatedWorld world_;
  rrr::OdometryChain<rrr::Pose2> chain_;
  std::vector<rrr::Pose2> odometry_;  // the odometry frame's poses
  std::vector<std::vector<int>> loops_at_;
  std::vector<ros::Time> stamps_;
  rrr::OdometryCovariance covariance_ = rrr::OdometryCovariance::Zero();
  int first_ = 0, last_ = 0;         // its part of the world's poses
  std::vector<int> first_of_robot_;  // of each robot's part (a fleet)
  int next_ = 0;
  ros::Publisher odom_pub_, loop_pub_, done_pub_;
  ros::Timer timer_;
};

}  // namespace rrr_ros

#endif  // RRR_ROS_SIMULATED_ROBOT_H_
