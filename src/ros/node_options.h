// Every parameter of rrr_node, read and checked in one place.
#ifndef RRR_ROS_NODE_OPTIONS_H_
#define RRR_ROS_NODE_OPTIONS_H_

#include <ros/node_handle.h>

#include <string>
#include <vector>

#include "rrr/graph/odometry_input.h"
#include "rrr/rrr/options.h"
#include "rrr/session/session_store.h"

namespace rrr_ros {

struct NodeOptions {
  int dimension = 2;  // 2: SE(2) graph (x, y, yaw); 3: SE(3)
  std::string map_frame = "map";
  std::string odom_frame = "odom";
  std::string base_frame = "base_link";
  // How odometry messages become keyframes and odometry edges (the
  // parameters keyframe/*, odometry/* and stamp_tolerance, in s): the same
  // for one robot and for each robot of a fleet.
  rrr::OdometryInputOptions odometry;
  // The session database (rrr::SessionStore): every input and decision is
  // recorded there, and a node started on an existing one resumes it.
  // Empty: no database.
  std::string database;
  // Keyframes between two checkpoints of the verifier's state in the
  // database, from which a resume starts instead of running every update
  // again (0: none).
  int checkpoint_keyframes = rrr::kDefaultCheckpointKeyframes;
  double tf_period = 0.1;  // s; map -> odom is re-broadcast this often
  // Least seconds between two messages on ~path and ~graph, and on
  // ~accepted_graph; each is built only while it has a subscriber.
  double display_period = 0.2;
  double graph_period = 1.0;
  // Inputs that may wait for the worker; more are refused and counted.
  size_t max_queue_length = 100000;
  rrr::RrrOptions rrr;
  // A fleet: the robots' names, each with its odometry on `<robot>/odom`
  // and its frames `<robot>/<odom_frame>` and `<robot>/<base_frame>`.
  // Empty: one robot, on `odom` in `odom_frame`.
  std::vector<std::string> robots;
  // A robot's odometry back at its frame's origin while its last reading was
  // more than this many metres from it restarted: the robot continues in a
  // new session that only loop closures join (rrr::SessionOptions; 0: not
  // looked for). A reading stamped before the last restarts it too.
  double restart_jump = 1.0;

  // Reads the private parameters of `nh`; throws std::invalid_argument naming
  // the first parameter that is missing a valid value.
  static NodeOptions Read(const ros::NodeHandle& nh);
};

}  // namespace rrr_ros

#endif  // RRR_ROS_NODE_OPTIONS_H_
