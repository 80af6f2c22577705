// rrr_node for a fleet: several robots, each with its odometry, and loop
// candidates within and between them, over one ROS master.
#ifndef RRR_ROS_FLEET_NODE_H_
#define RRR_ROS_FLEET_NODE_H_

#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <tf2_ros/transform_broadcaster.h>

#include <functional>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "node_options.h"
#include "node_status.h"
#include "node_worker.h"
#include "rrr/rrr/decision_delta.h"
#include "rrr/session/fleet_session.h"
#include "rrr_slam/AcceptedGraph.h"
#include "rrr_slam/Decisions.h"
#include "rrr_slam/Finish.h"
#include "rrr_slam/FleetLoopClosure.h"
#include "rrr_slam/GetAcceptedGraph.h"
#include "rrr_slam/GetDecisions.h"
#include "rrr_slam/LoopClosure.h"
#include "rrr_slam/SaveGraph.h"

namespace rrr_ros {

// The adapter between ROS and an rrr::FleetSession (a fleet and its session
// database; README, "A fleet of robots").
// Robot r's odometry comes on `<r>/odom`; candidates on
// `fleet_loop_closures` name robot and keyframe (by id or stamp) at both
// ends (those on `loop_closures`, as a single robot's front-end sends them,
// are taken as within the first robot). Callbacks only queue their input; one
// worker (the thread that calls Run()) owns the fleet, takes the queue in
// batches and publishes: `~<r>/keyframes`, `~<r>/path` (robot r's sessions in
// the map of its current one), `~graph` (markers, a colour per robot),
// `~decisions` (the candidates new or changed at each update),
// `~accepted_graph` (the map in `map_frame`), `/diagnostics`
// (every second, as one robot's node does), and on tf
// `<map frame> → <r>/<odom_frame>` for every robot with a keyframe. The map
// that holds the first robot's first session is `map_frame`; a map that
// does not is named after the robot of its oldest session, `<r>/map`, or
// `<r>/map_<k>` if that is its session k > 0. With `database` set, the
// fleet's inputs and decisions are recorded there at each update, and a node
// started on it resumes them (each robot then in a new session).
template <class Pose>
class FleetNode {
 public:
  // Advertises and subscribes; throws std::invalid_argument on bad options.
  FleetNode(ros::NodeHandle& nh, ros::NodeHandle& private_nh,
            const NodeOptions& options);
  ~FleetNode();

  // The worker: judges and publishes on the calling thread until Stop().
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

  // ROS threads: queue and return.
  bool OnFinish(rrr_slam::Finish::Request& req,
                rrr_slam::Finish::Response& res);
  bool OnSaveGraph(rrr_slam::SaveGraph::Request& req,
                   rrr_slam::SaveGraph::Response& res);
  bool OnGetDecisions(rrr_slam::GetDecisions::Request& req,
                      rrr_slam::GetDecisions::Response& res);
  bool OnGetAcceptedGraph(rrr_slam::GetAcceptedGraph::Request& req,
                          rrr_slam::GetAcceptedGraph::Response& res);
  void OnTfTimer(const ros::TimerEvent& event);

  // Takes up the session database (FleetSession::Resume) and reports it;
  // throws std::invalid_argument naming the database if it cannot.
  void Resume();
  // Worker.
  void Process(const RobotOdometry& odometry);
  void Process(const rrr_slam::FleetLoopClosure::ConstPtr& msg);
  void Process(const rrr_slam::LoopClosure::ConstPtr& msg);
  // Adds `loop` (message `seq`) between robots `from` and `to`.
  void AddCandidate(uint32_t seq, int from, int to,
                    const rrr_slam::LoopClosure& loop);
  // The accepted graph of the map in `map_frame`: every robot's sessions in
  // it, each pose named by robot and keyframe id.
  rrr_slam::AcceptedGraph AcceptedGraph() const;
  // Sets the counts of keyframes, candidates and their states in
  // status_.counts from the fleet; under status_.mutex once the worker runs.
  void CountState();
  // Runs the fleet's update (or Finish) and publishes.
  void UpdateAndPublish(bool finish);
  // The candidates `carried` (ascending) with their state and reason, the
  // `changes` since the last message marked; `full`: every candidate.
  rrr_slam::Decisions DecisionsMsg(
      const std::vector<int>& carried,
      const std::vector<rrr::DecisionChange>& changes, bool full) const;
  // The frame of map `map` (a chain index; see the class comment).
  std::string MapFrame(int map) const;
  std::string RobotFrame(int robot, const std::string& frame) const;

  const NodeOptions options_;
  ros::NodeHandle nh_, private_nh_;
  std::vector<ros::Subscriber> odom_subs_;
  ros::Subscriber fleet_loop_sub_, loop_sub_;
  std::vector<ros::Publisher> keyframe_pubs_, path_pubs_;
  ros::Publisher marker_pub_, decision_pub_, graph_pub_;
  ros::ServiceServer finish_srv_, save_srv_, decisions_srv_, graph_srv_;
  ros::Timer tf_timer_;
  tf2_ros::TransformBroadcaster tf_broadcaster_;
  Worker worker_;
  NodeStatus status_;  // ~get_status and /diagnostics

  // Worker state.
  rrr::FleetSession<Pose> session_;
  bool changed_ = false;  // keyframes or decisions since the last publishing
  ros::WallTime last_published_, last_graph_published_;
  uint64_t taken_since_update_ = 0;
  rrr::DecisionDelta decision_delta_;  // what ~decisions carries next
  int refused_by_stamp_counted_ = 0;  // in status_.counts.skipped_unknown_poses

  // Shared with the ROS threads under `status_.mutex`.
  std::vector<geometry_msgs::TransformStamped> map_to_odom_;
};

}  // namespace rrr_ros

#endif  // RRR_ROS_FLEET_NODE_H_
