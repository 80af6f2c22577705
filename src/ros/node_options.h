// Every parameter of rrr_node, read and checked in one place.
#ifndef RRR_ROS_NODE_OPTIONS_H_
#define RRR_ROS_NODE_OPTIONS_H_

#include <ros/node_handle.h>

#include <string>
#include <vector>

#include "rrr/rrr/options.h"
#include "rrr/session/session_store.h"

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
  // An odometry edge's information (rrr::OdometryNoiseModel): from the
  // change of the messages' pose covariance between the keyframes when it
  // is positive definite and this is true; otherwise from
  // `odometry_information` (diagonal, x y yaw or x y z rx ry rz: of one metre
  // or radian of motion) scaled by the metres plus radians travelled, at
  // least `odometry_min_motion`.
  bool use_odometry_covariance = true;
  std::vector<double> odometry_information;
  double odometry_min_motion = 0.05;
  // A loop named by stamps takes the keyframes nearest in time within this.
  // The session database (rrr::SessionStore): every input and decision is
  // recorded there, and a node started on an existing one resumes it.
  // Empty: no database.
  std::string database;
  // Keyframes between two checkpoints of the verifier's state in the
  // database, from which a resume starts instead of running every update
  // again (0: none).
  int checkpoint_keyframes = rrr::kDefaultCheckpointKeyframes;
  double stamp_tolerance = 0.1;  // s
  double tf_period = 0.1;        // s; map -> odom is re-broadcast this often
  // Least seconds between two messages on ~path and ~graph, and on
  // ~accepted_graph; each is built only while it has a subscriber.
  double display_period = 0.2;
  double graph_period = 1.0;
  // Inputs that may wait for the worker; more are refused and counted.
  size_t max_queue_length = 100000;
  rrr::RrrOptions rrr;
  // A fleet (FleetNode): the robots' names, each with its odometry on
  // `<robot>/odom` and its frames `<robot>/<odom_frame>` and
  // `<robot>/<base_frame>`. Empty: one robot (VerifierNode).
  std::vector<std::string> robots;
  // A fleet's robot whose odometry jumps more than this many metres between
  // two messages restarted: it continues in a new session (0: never).
  double restart_jump = 1.0;

  // Reads the private parameters of `nh`; throws std::invalid_argument naming
  // the first parameter that is missing a valid value.
  static NodeOptions Read(const ros::NodeHandle& nh);
};

}  // namespace rrr_ros

#endif  // RRR_ROS_NODE_OPTIONS_H_
