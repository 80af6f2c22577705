// rrr_node: incremental RRR next to a place-recognition front-end.
#ifndef RRR_ROS_VERIFIER_NODE_H_
#define RRR_ROS_VERIFIER_NODE_H_

#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <tf2_ros/transform_broadcaster.h>

#include <functional>
#include <memory>
#include <variant>
#include <vector>

#include "node_options.h"
#include "node_status.h"
#include "node_worker.h"
#include "rrr/rrr/decision_delta.h"
#include "rrr/session/robot_session.h"
#include "rrr_slam/Finish.h"
#include "rrr_slam/GetAcceptedGraph.h"
#include "rrr_slam/GetDecisions.h"
#include "rrr_slam/LoopClosure.h"
#include "rrr_slam/SaveGraph.h"

namespace rrr_ros {

// The adapter between ROS and an rrr::RobotSession (the keyframes, the
// decision procedure and the session database of one robot). Callbacks only
// queue their input; one worker (the thread that calls Run()) owns the
// session, takes the queue in batches (so it catches up when inputs come
// faster than it judges), converts the messages for it, and publishes.
// Services that need the session are queued as well, so they see every input
// received before them.
template <class Pose>
class VerifierNode {
 public:
  // Advertises and subscribes; throws std::invalid_argument on bad options.
  VerifierNode(ros::NodeHandle& nh, ros::NodeHandle& private_nh,
               const NodeOptions& options);
  ~VerifierNode();

  // The worker: judges and publishes on the calling thread until Stop().
  // Run it on the process's main thread: the main arena keeps the memory a
  // whole-map factorization frees for the next one, where a thread's own
  // arena, which holds no block over 64 MB, would map it afresh each time.
  void Run();
  // Makes Run() return once the inputs taken so far are judged; any thread.
  void Stop();

 private:
  using Information = typename rrr::Constraint<Pose>::Information;
  using Worker =
      NodeWorker<nav_msgs::Odometry::ConstPtr, rrr_slam::LoopClosure::ConstPtr>;

  // ROS threads: record and return.
  void OnOdometry(const nav_msgs::Odometry::ConstPtr& msg);
  void OnLoopClosure(const rrr_slam::LoopClosure::ConstPtr& msg);
  bool OnSaveGraph(rrr_slam::SaveGraph::Request& req,
                   rrr_slam::SaveGraph::Response& res);
  bool OnFinish(rrr_slam::Finish::Request& req,
                rrr_slam::Finish::Response& res);
  bool OnGetDecisions(rrr_slam::GetDecisions::Request& req,
                      rrr_slam::GetDecisions::Response& res);
  bool OnGetAcceptedGraph(rrr_slam::GetAcceptedGraph::Request& req,
                          rrr_slam::GetAcceptedGraph::Response& res);
  void OnTfTimer(const ros::TimerEvent& event);

  // Worker (taking in the inputs: verifier_node_inputs.cc).
  void Process(const nav_msgs::Odometry::ConstPtr& msg);
  void Process(const rrr_slam::LoopClosure::ConstPtr& msg);
  // Runs the decision procedure (or, with `finish`, judges everything) and
  // publishes what changed: ~decisions at once, the larger messages while
  // subscribed, at most every display_period / graph_period s (at once at
  // `finish`).
  void UpdateAndPublish(bool finish);
  // The latched outputs kept up to date for their subscribers, as bits.
  enum Output : unsigned {
    kPath = 1u,     // ~path
    kMarkers = 2u,  // ~graph
    kGraph = 4u,    // ~accepted_graph
    kAllOutputs = 7u
  };
  // Publishes the outputs that are out of date and subscribed, if their
  // period has passed or they are among the bits of `now`.
  void PublishDue(unsigned now);
  // Takes up the session database (RobotSession::Resume) and reports it.
  void Resume();
  // How warnings name the inputs: "<kind> message <seq>".
  static constexpr const char* kOdometry = "odometry";
  static constexpr const char* kLoopClosure = "loop closure";
  // Counts a loop candidate the session skipped under its reason and warns
  // (throttled).
  void Skip(const rrr::SkippedMessage& skipped);

  const NodeOptions options_;
  ros::NodeHandle nh_, private_nh_;
  ros::Subscriber odom_sub_, loop_sub_;
  ros::Publisher keyframe_pub_, path_pub_, marker_pub_, decision_pub_,
      graph_pub_;
  ros::ServiceServer save_srv_, finish_srv_, decisions_srv_, graph_srv_;
  ros::Timer tf_timer_;
  tf2_ros::TransformBroadcaster tf_broadcaster_;

  Worker worker_;      // between the callbacks and the worker
  NodeStatus status_;  // ~get_status and /diagnostics

  // Worker state (touched only by the worker).
  rrr::RobotSession<Pose> session_;
  bool new_keyframes_ = false;
  uint64_t taken_since_update_ = 0;    // inputs taken in since the last update
  rrr::DecisionDelta decision_delta_;  // what ~decisions carries next
  // Whether ~path, ~graph and ~accepted_graph are behind the state.
  bool path_stale_ = false, markers_stale_ = false, graph_stale_ = false;
  ros::WallTime last_path_, last_markers_, last_graph_;  // last published

  // Shared with the ROS threads under `status_.mutex`.
  geometry_msgs::TransformStamped map_to_odom_;
  bool have_map_to_odom_ = false;
};

}  // namespace rrr_ros

#endif  // RRR_ROS_VERIFIER_NODE_H_
