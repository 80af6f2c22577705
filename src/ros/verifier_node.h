// rrr_node: incremental RRR next to a place-recognition front-end, for one
// robot or a fleet.
#ifndef RRR_ROS_VERIFIER_NODE_H_
#define RRR_ROS_VERIFIER_NODE_H_

#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <tf2_ros/transform_broadcaster.h>

#include <cstdint>
#include <string>
#include <vector>

#include "node_options.h"
#include "node_status.h"
#include "node_worker.h"
#include "rrr/rrr/decision_delta.h"
#include "rrr/session/session.h"
#include "rrr_slam/Finish.h"
#include "rrr_slam/FleetLoopClosure.h"
#include "rrr_slam/GetAcceptedGraph.h"
#include "rrr_slam/GetDecisions.h"
#include "rrr_slam/LoopClosure.h"
#include "rrr_slam/SaveGraph.h"

namespace rrr_ros {

// The adapter between ROS and an rrr::Session (doc/node.md). One robot
// (`robots` empty): odometry on `odom`, candidates on `loop_closures`,
// `~keyframes` and `~path`, tf `map_frame → odom_frame`. A fleet: robot r's
// odometry on `<r>/odom`, candidates on `fleet_loop_closures` (those on
// `loop_closures` are within the first robot), `~<r>/keyframes`,
// `~<r>/path`, tf `<map> → <r>/<odom_frame>`. Both: `~graph` (markers),
// `~decisions`, `~accepted_graph`, the services and /diagnostics. The map
// holding the first robot's first session is `map_frame`; another is named
// after the robot of its oldest session, `<r>/map`, or `<r>/map_<k>` for its
// session k > 0. Callbacks only queue their input; one worker (the thread
// that calls Run()) owns the session, takes the queue in batches (so it
// catches up when inputs come faster than it judges), converts the messages
// for it, and publishes. Services that need the session are queued as well,
// so they see every input received before them.
template <class Pose>
class VerifierNode {
 public:
  // Advertises and subscribes; throws std::invalid_argument on bad options
  // or a database that cannot be resumed.
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
  struct RobotOdometry {
    int robot;
    nav_msgs::Odometry::ConstPtr msg;
  };
  using Worker = NodeWorker<RobotOdometry, rrr_slam::FleetLoopClosure::ConstPtr,
                            rrr_slam::LoopClosure::ConstPtr>;
  // A latched output kept up to date for its subscribers: built only while
  // it has one, at most every `period` s unless `now`.
  struct Output {
    ros::Publisher pub;
    bool stale = false;  // behind the state
    bool now = false;    // a subscriber joined: due at once
    ros::WallTime last;  // last published
  };

  // ROS threads: services queue their work and wait for it.
  bool OnSaveGraph(rrr_slam::SaveGraph::Request& req,
                   rrr_slam::SaveGraph::Response& res);
  bool OnFinish(rrr_slam::Finish::Request& req,
                rrr_slam::Finish::Response& res);
  bool OnGetDecisions(rrr_slam::GetDecisions::Request& req,
                      rrr_slam::GetDecisions::Response& res);
  bool OnGetAcceptedGraph(rrr_slam::GetAcceptedGraph::Request& req,
                          rrr_slam::GetAcceptedGraph::Response& res);
  void OnTfTimer(const ros::TimerEvent& event);
  // Advertises `topic` (private) as a latched Output.
  template <class Message>
  void Advertise(const std::string& topic, Output* output);

  // Worker (taking in the inputs: verifier_node_inputs.cc).
  void Process(const RobotOdometry& odometry);
  void Process(const rrr_slam::FleetLoopClosure::ConstPtr& msg);
  void Process(const rrr_slam::LoopClosure::ConstPtr& msg);
  // Adds `loop` (message `seq`) between robots `from` and `to`.
  void AddCandidate(uint32_t seq, int from, int to,
                    const rrr_slam::LoopClosure& loop);
  // Counts a loop candidate the session skipped under its reason and warns
  // (throttled).
  void Skip(const rrr::SkippedMessage& skipped);
  // Runs the decision procedure (or, with `finish`, judges everything) and
  // publishes what changed: ~decisions at once, the larger messages while
  // subscribed, at most every display_period / graph_period s (at once at
  // `finish`).
  void UpdateAndPublish(bool finish);
  // Publishes the outputs that are stale, subscribed and due (all that are
  // stale and subscribed if `all`).
  void PublishDue(bool all);
  // Takes up the session database (Session::Resume) and reports it.
  void Resume();
  // `frame` of robot `robot`: "<robot>/<frame>" in a fleet, else `frame`.
  std::string RobotFrame(int robot, const std::string& frame) const;
  // The frame of map `map` (a chain; see the class comment).
  std::string MapFrame(int map) const;

  const NodeOptions options_;
  ros::NodeHandle nh_, private_nh_;
  std::vector<ros::Subscriber> subs_;
  std::vector<ros::Publisher> keyframe_pubs_;  // by robot
  ros::Publisher decision_pub_;
  std::vector<Output> paths_;  // by robot
  Output markers_, graph_;
  ros::ServiceServer save_srv_, finish_srv_, decisions_srv_, graph_srv_;
  ros::Timer tf_timer_;
  tf2_ros::TransformBroadcaster tf_broadcaster_;

  Worker worker_;      // between the callbacks and the worker
  NodeStatus status_;  // ~get_status and /diagnostics

  // Worker state (touched only by the worker).
  rrr::Session<Pose> session_;
  bool new_keyframes_ = false;
  uint64_t taken_since_update_ = 0;    // inputs taken in since the last update
  rrr::DecisionDelta decision_delta_;  // what ~decisions carries next

  // Shared with the ROS threads under `status_.mutex`: map → odom by robot
  // (an empty child frame before the robot's first keyframe).
  std::vector<geometry_msgs::TransformStamped> map_to_odom_;
};

}  // namespace rrr_ros

#endif  // RRR_ROS_VERIFIER_NODE_H_
