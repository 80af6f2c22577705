// Every parameter of rrr_node, read and checked in one place.
#ifndef RRR_ROS_NODE_OPTIONS_H_
#define RRR_ROS_NODE_OPTIONS_H_

#include <ros/node_handle.h>

#include <string>
#include <vector>

#include "rrr/rrr/options.h"

namespace rrr_ros {

struct NodeOptions {
  int dimension = 2;  // 2: SE(2) graph (x, y, yaw); 3: SE(3)
  std::string map_frame = "map";
  std::string odom_frame = "odom";
  std::string base_frame = "base_link";
  // A keyframe is made when the robot moved more than this since the last
  // one (0 and 0: every odometry message).
  double keyframe_translation = 0.0;  // m
  double keyframe_rotation = 0.0;     // rad
  // Take an odometry message's pose covariance as the covariance of the
  // motion since the previous keyframe when it is valid (as `rrr to-bag`
  // writes it); otherwise, or when false, use `odometry_information`.
  bool use_odometry_covariance = true;
  // Diagonal information of an odometry edge (x y yaw, or x y z rx ry rz).
  std::vector<double> odometry_information;
  // A loop named by stamps takes the keyframes nearest in time within this.
  double stamp_tolerance = 0.1;  // s
  double tf_period = 0.1;        // s; map -> odom is re-broadcast this often
  rrr::RrrOptions rrr;

  // Reads the private parameters of `nh`; throws std::invalid_argument naming
  // the first parameter that is missing a valid value.
  static NodeOptions Read(const ros::NodeHandle& nh);
};

}  // namespace rrr_ros

#endif  // RRR_ROS_NODE_OPTIONS_H_
