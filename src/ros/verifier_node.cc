#include "verifier_node.h"

#include <nav_msgs/Path.h>
#include <visualization_msgs/MarkerArray.h>

#include <algorithm>
#include <chrono>
#include <mutex>
#include <stdexcept>
#include <type_traits>

#include "graph_messages.h"
#include "msg_conversion.h"
#include "rrr_slam/AcceptedGraph.h"
#include "rrr_slam/Decisions.h"
#include "rrr_slam/Keyframe.h"
#include "status_messages.h"

namespace rrr_ros {
namespace {

constexpr int kQueueSize =
    10000;  // ROS subscriber queues (ours: max_queue_length)

rrr::SessionOptions SessionOptionsOf(const NodeOptions& options) {
  rrr::SessionOptions session;
  session.rrr = options.rrr;
  session.odometry = options.odometry;
  session.database = options.database;
  session.checkpoint_keyframes = options.checkpoint_keyframes;
  session.restart_jump = options.restart_jump;
  return session;
}

// One robot (an empty name) or the fleet's.
std::vector<std::string> RobotsOf(const NodeOptions& options) {
  return options.robots.empty() ? std::vector<std::string>{""} : options.robots;
}

}  // namespace

template <class Pose>
VerifierNode<Pose>::VerifierNode(ros::NodeHandle& nh,
                                 ros::NodeHandle& private_nh,
                                 const NodeOptions& options)
    : options_(options),
      nh_(nh),
      private_nh_(private_nh),
      paths_(RobotsOf(options).size()),
      worker_(options.max_queue_length),
      session_(RobotsOf(options), SessionOptionsOf(options),
               [this](const rrr::SkippedMessage& s) { Skip(s); }),
      map_to_odom_(RobotsOf(options).size()) {
  status_.counts.procedure = rrr::ToString(options_.rrr.procedure);
  if (!options_.database.empty()) Resume();
  SetSessionState(session_, &status_.counts);
  const int robots = static_cast<int>(session_.robots().size());
  for (int r = 0; r < robots; ++r) {
    keyframe_pubs_.push_back(private_nh_.advertise<rrr_slam::Keyframe>(
        RobotFrame(r, "keyframes"), 1000));
    Advertise<nav_msgs::Path>(RobotFrame(r, "path"), &paths_[r]);
    paths_[r].stale = new_keyframes_;
  }
  Advertise<visualization_msgs::MarkerArray>("graph", &markers_);
  Advertise<rrr_slam::AcceptedGraph>("accepted_graph", &graph_);
  markers_.stale = graph_.stale = new_keyframes_;
  decision_pub_ =
      private_nh_.advertise<rrr_slam::Decisions>("decisions", 100, true);
  save_srv_ = private_nh_.advertiseService("save_graph",
                                           &VerifierNode::OnSaveGraph, this);
  finish_srv_ =
      private_nh_.advertiseService("finish", &VerifierNode::OnFinish, this);
  decisions_srv_ = private_nh_.advertiseService(
      "get_decisions", &VerifierNode::OnGetDecisions, this);
  graph_srv_ = private_nh_.advertiseService(
      "get_accepted_graph", &VerifierNode::OnGetAcceptedGraph, this);
  tf_timer_ = nh_.createTimer(ros::Duration(options_.tf_period),
                              &VerifierNode::OnTfTimer, this);
  const auto hints = ros::TransportHints().tcpNoDelay();
  for (int r = 0; r < robots; ++r) {
    subs_.push_back(nh_.subscribe<nav_msgs::Odometry>(
        RobotFrame(r, "odom"), kQueueSize,
        [this, r](const nav_msgs::Odometry::ConstPtr& msg) {
          ++status_.odometry_received;
          worker_.Enqueue(RobotOdometry{r, msg}, "odometry", msg->header.seq);
        },
        ros::VoidConstPtr(), hints));
  }
  subs_.push_back(nh_.subscribe<rrr_slam::LoopClosure>(
      "loop_closures", kQueueSize,
      [this](const rrr_slam::LoopClosure::ConstPtr& msg) {
        ++status_.loops_received;
        worker_.Enqueue(msg, "loop closure", msg->header.seq);
      },
      ros::VoidConstPtr(), hints));
  if (robots > 1) {
    subs_.push_back(nh_.subscribe<rrr_slam::FleetLoopClosure>(
        "fleet_loop_closures", kQueueSize,
        [this](const rrr_slam::FleetLoopClosure::ConstPtr& msg) {
          ++status_.loops_received;
          worker_.Enqueue(msg, "fleet loop closure", msg->loop.header.seq);
        },
        ros::VoidConstPtr(), hints));
  }
  status_.Serve(nh_, private_nh_, [this](rrr_slam::GetStatus::Response* s) {
    worker_.SetQueueStatus(s);
  });
}

template <class Pose>
template <class Message>
void VerifierNode<Pose>::Advertise(const std::string& topic, Output* output) {
  // A subscriber that joins gets the state at once if the latched message of
  // its topic is out of date (after ~finish no update would send it).
  output->pub = private_nh_.advertise<Message>(
      topic, 1,
      [this, output](const ros::SingleSubscriberPublisher&) {
        worker_.Enqueue([this, output] {
          output->now = true;
          PublishDue(false);
          output->now = false;
        });
      },
      {}, {}, true);
}

template <class Pose>
VerifierNode<Pose>::~VerifierNode() {
  for (ros::Subscriber& sub : subs_) sub.shutdown();
  worker_.Stop();
}

template <class Pose>
void VerifierNode<Pose>::Stop() {
  worker_.Stop();
}

template <class Pose>
void VerifierNode<Pose>::Resume() {
  rrr::ResumeSummary summary;
  try {
    summary = session_.Resume();
  } catch (const rrr::SessionError& e) {
    throw std::invalid_argument(std::string("database: ") + e.what());
  }
  const char* database = options_.database.c_str();
  if (summary.differing_decisions > 0) {
    ROS_WARN(
        "rrr_node: %d decisions differ from the ones %s recorded (were the "
        "options changed?)",
        summary.differing_decisions, database);
  }
  if (summary.checkpoint_of_other_options) {
    ROS_WARN(
        "rrr_node: the checkpoint in %s was saved under other options; "
        "every recorded update was run again",
        database);
  }
  rrr_slam::GetStatus::Response& counts = status_.counts;
  counts.database = options_.database;
  counts.resumed_keyframes = summary.keyframes;
  counts.resumed_candidates = summary.candidates;
  counts.updates = summary.updates;
  counts.resumed_waiting_by_stamp = session_.num_waiting_by_stamp();
  counts.resumed_from_update = summary.checkpoint_update;
  new_keyframes_ = summary.keyframes > 0;
  ROS_INFO(
      "rrr_node: session %s: resumed %d keyframes in %d sessions, %d "
      "candidates (%d waiting by stamp), %d updates (from the checkpoint "
      "after update %lld; 0: none)",
      database, summary.keyframes, session_.num_chains(), summary.candidates,
      session_.num_waiting_by_stamp(), summary.updates,
      static_cast<long long>(summary.checkpoint_update));
}

template <class Pose>
std::string VerifierNode<Pose>::RobotFrame(int robot,
                                           const std::string& frame) const {
  return options_.robots.empty() ? frame : options_.robots[robot] + "/" + frame;
}

template <class Pose>
std::string VerifierNode<Pose>::MapFrame(int map) const {
  if (map == session_.MapOfChain(0)) return options_.map_frame;
  const int robot = session_.robot_of_chain(map);
  const std::vector<int>& sessions = session_.sessions(robot);
  const auto k =
      std::find(sessions.begin(), sessions.end(), map) - sessions.begin();
  return RobotFrame(robot, options_.map_frame) +
         (k == 0 ? "" : "_" + std::to_string(k));
}

// ---- ROS threads ----------------------------------------------------------

template <class Pose>
bool VerifierNode<Pose>::OnSaveGraph(rrr_slam::SaveGraph::Request& req,
                                     rrr_slam::SaveGraph::Response& res) {
  worker_.RunOnWorker(
      [&] { SaveGraphFile(session_, req.path, req.with_candidates, &res); });
  return true;
}

template <class Pose>
bool VerifierNode<Pose>::OnFinish(rrr_slam::Finish::Request&,
                                  rrr_slam::Finish::Response& res) {
  worker_.RunOnWorker([&] {
    UpdateAndPublish(true);
    std::lock_guard<std::mutex> lock(status_.mutex);
    res.accepted = status_.counts.accepted;
    res.rejected = status_.counts.rejected;
    res.pending = status_.counts.pending;
    res.waiting = status_.counts.waiting;
  });
  return true;
}

template <class Pose>
bool VerifierNode<Pose>::OnGetDecisions(rrr_slam::GetDecisions::Request&,
                                        rrr_slam::GetDecisions::Response& res) {
  worker_.RunOnWorker([&] {
    std::vector<int> every(session_.verifier().num_candidates());
    for (size_t c = 0; c < every.size(); ++c) every[c] = static_cast<int>(c);
    res.decisions = DecisionsMsg(session_, every, {}, true, options_.map_frame);
  });
  return true;
}

template <class Pose>
bool VerifierNode<Pose>::OnGetAcceptedGraph(
    rrr_slam::GetAcceptedGraph::Request&,
    rrr_slam::GetAcceptedGraph::Response& res) {
  worker_.RunOnWorker([&] {
    res.graph = AcceptedGraphMsg(
        session_, session_.num_chains() > 0 ? session_.MapOfChain(0) : -1,
        options_.map_frame);
  });
  return true;
}

template <class Pose>
void VerifierNode<Pose>::OnTfTimer(const ros::TimerEvent&) {
  std::lock_guard<std::mutex> lock(status_.mutex);
  // Stamped ahead so that lookups at the latest odometry time succeed.
  const ros::Time stamp = ros::Time::now() + ros::Duration(options_.tf_period);
  for (geometry_msgs::TransformStamped t : map_to_odom_) {
    if (t.child_frame_id.empty()) continue;  // no keyframe yet
    t.header.stamp = stamp;
    tf_broadcaster_.sendTransform(t);
  }
}

// ---- Worker thread ---------------------------------------------------------

template <class Pose>
void VerifierNode<Pose>::Run() {
  worker_.Run(
      [this](const auto& msg, typename Worker::Clock::time_point arrival) {
        Process(msg);
        if constexpr (!std::is_same_v<std::decay_t<decltype(msg)>,
                                      RobotOdometry>) {
          status_.NoteCandidateArrival(arrival);
        }
        ++taken_since_update_;
      },
      [this] { UpdateAndPublish(false); });
}

template <class Pose>
void VerifierNode<Pose>::UpdateAndPublish(bool finish) {
  const auto start = std::chrono::steady_clock::now();
  const typename rrr::Session<Pose>::Updated updated = session_.Update(finish);
  const std::vector<rrr::DecisionChange>& changes = updated.changes;
  status_.CountDatabaseError(updated.store_error);
  graph_.stale = graph_.stale || updated.accepted_changed || finish;
  const bool display_changed =
      updated.accepted_changed || !changes.empty() || new_keyframes_;
  for (Output& path : paths_) path.stale = path.stale || display_changed;
  markers_.stale = markers_.stale || display_changed;
  new_keyframes_ = false;
  const std::vector<int> carried =
      decision_delta_.Next(session_.verifier(), changes);
  if (!carried.empty() || finish) {
    decision_pub_.publish(
        DecisionsMsg(session_, carried, changes, false, options_.map_frame));
  }
  PublishDue(finish);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();

  std::lock_guard<std::mutex> lock(status_.mutex);
  const ros::Time stamp = ros::Time::now() + ros::Duration(options_.tf_period);
  for (int r = 0; r < static_cast<int>(map_to_odom_.size()); ++r) {
    const std::optional<Pose> correction = session_.MapToOdom(r);
    if (!correction) continue;
    geometry_msgs::TransformStamped& t = map_to_odom_[r];
    t.header.frame_id = MapFrame(session_.MapOfRobot(r));
    t.header.stamp = stamp;
    t.child_frame_id = RobotFrame(r, options_.odom_frame);
    t.transform = ToRosTransform(*correction);
    tf_broadcaster_.sendTransform(t);
  }
  SetSessionState(session_, &status_.counts);
  ++status_.counts.updates;
  status_.counts.inputs_processed += taken_since_update_;
  taken_since_update_ = 0;
  status_.timings.AddUpdate(seconds);
  status_.AddCandidateLatencies();
}

template <class Pose>
void VerifierNode<Pose>::PublishDue(bool all) {
  const ros::WallTime time = ros::WallTime::now();
  const auto due = [&](Output* output, double period) {
    if (!output->stale || output->pub.getNumSubscribers() == 0) return false;
    if (!all && !output->now && (time - output->last).toSec() < period) {
      return false;
    }
    output->stale = output->now = false;
    output->last = time;
    return true;
  };
  const auto frames = [this](int map) { return MapFrame(map); };
  for (int r = 0; r < static_cast<int>(paths_.size()); ++r) {
    if (session_.MapOfRobot(r) >= 0 &&
        due(&paths_[r], options_.display_period)) {
      paths_[r].pub.publish(
          PathMsg(session_, r, MapFrame(session_.MapOfRobot(r))));
    }
  }
  if (due(&markers_, options_.display_period)) {
    markers_.pub.publish(GraphMarkers(session_, frames));
  }
  if (due(&graph_, options_.graph_period)) {
    graph_.pub.publish(AcceptedGraphMsg(
        session_, session_.num_chains() > 0 ? session_.MapOfChain(0) : -1,
        options_.map_frame));
  }
}

template class VerifierNode<rrr::Pose2>;
template class VerifierNode<rrr::Pose3>;

}  // namespace rrr_ros
