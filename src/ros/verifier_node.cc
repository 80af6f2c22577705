#include "verifier_node.h"

#include <nav_msgs/Path.h>
#include <visualization_msgs/MarkerArray.h>

#include <chrono>
#include <cstdint>
#include <mutex>
#include <type_traits>

#include "graph_messages.h"
#include "msg_conversion.h"
#include "rrr/io/g2o.h"
#include "rrr_slam/AcceptedGraph.h"
#include "rrr_slam/Decisions.h"
#include "rrr_slam/Keyframe.h"
#include "status_messages.h"

namespace rrr_ros {
namespace {

constexpr int kQueueSize =
    10000;  // ROS subscriber queues (ours: max_queue_length)

rrr::RobotSessionOptions SessionOptionsOf(const NodeOptions& options) {
  rrr::RobotSessionOptions session;
  session.rrr = options.rrr;
  session.odometry = options.odometry;
  session.database = options.database;
  session.checkpoint_keyframes = options.checkpoint_keyframes;
  session.restart_jump = options.restart_jump;
  return session;
}

}  // namespace

template <class Pose>
VerifierNode<Pose>::VerifierNode(ros::NodeHandle& nh,
                                 ros::NodeHandle& private_nh,
                                 const NodeOptions& options)
    : options_(options),
      nh_(nh),
      private_nh_(private_nh),
      worker_(options.max_queue_length),
      session_(SessionOptionsOf(options),
               [this](const rrr::SkippedMessage& s) { Skip(s); }) {
  status_.counts.procedure = rrr::ToString(options_.rrr.procedure);
  if (!options_.database.empty()) Resume();
  SetVerifierState(session_.verifier(), &status_.counts);
  keyframe_pub_ = private_nh_.advertise<rrr_slam::Keyframe>("keyframes", 1000);
  // A subscriber that joins gets the state at once if the latched message of
  // its topic is out of date (after ~finish no update would send it).
  const auto joined = [this](Output output) -> ros::SubscriberStatusCallback {
    return [this, output](const ros::SingleSubscriberPublisher&) {
      worker_.Enqueue([this, output] { PublishDue(output); });
    };
  };
  path_pub_ = private_nh_.advertise<nav_msgs::Path>("path", 1, joined(kPath),
                                                    {}, {}, true);
  marker_pub_ = private_nh_.advertise<visualization_msgs::MarkerArray>(
      "graph", 1, joined(kMarkers), {}, {}, true);
  decision_pub_ =
      private_nh_.advertise<rrr_slam::Decisions>("decisions", 100, true);
  graph_pub_ = private_nh_.advertise<rrr_slam::AcceptedGraph>(
      "accepted_graph", 1, joined(kGraph), {}, {}, true);
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
  odom_sub_ = nh_.subscribe("odom", kQueueSize, &VerifierNode::OnOdometry, this,
                            ros::TransportHints().tcpNoDelay());
  loop_sub_ =
      nh_.subscribe("loop_closures", kQueueSize, &VerifierNode::OnLoopClosure,
                    this, ros::TransportHints().tcpNoDelay());
  status_.Serve(nh_, private_nh_, [this](rrr_slam::GetStatus::Response* s) {
    worker_.SetQueueStatus(s);
  });
}

template <class Pose>
VerifierNode<Pose>::~VerifierNode() {
  odom_sub_.shutdown();
  loop_sub_.shutdown();
  worker_.Stop();
}

template <class Pose>
void VerifierNode<Pose>::Stop() {
  worker_.Stop();
}

template <class Pose>
void VerifierNode<Pose>::Resume() {
  const rrr::ResumeSummary summary = status_.CountResumed(
      options_.database, [&] { return session_.Resume(); },
      "were the options changed?");
  if (summary.checkpoint_of_other_options) {
    ROS_WARN(
        "rrr_node: the checkpoint in %s was saved under other options; "
        "every recorded update was run again",
        options_.database.c_str());
  }
  status_.counts.resumed_waiting_by_stamp = summary.waiting_by_stamp;
  status_.counts.resumed_from_update =
      static_cast<uint64_t>(summary.checkpoint_update);
  status_.counts.waiting_by_stamp =
      static_cast<uint32_t>(session_.waiting_by_stamp());
  ROS_INFO(
      "rrr_node: session %s: resumed %d keyframes, %d candidates (and %d "
      "waiting by stamp), %d updates (from the checkpoint after update "
      "%lld; 0: none)",
      options_.database.c_str(), summary.keyframes, summary.candidates,
      summary.waiting_by_stamp, summary.updates,
      static_cast<long long>(summary.checkpoint_update));
}

// ---- ROS threads ----------------------------------------------------------

template <class Pose>
void VerifierNode<Pose>::OnOdometry(const nav_msgs::Odometry::ConstPtr& msg) {
  ++status_.odometry_received;
  worker_.Enqueue(msg, kOdometry, msg->header.seq);
}

template <class Pose>
void VerifierNode<Pose>::OnLoopClosure(
    const rrr_slam::LoopClosure::ConstPtr& msg) {
  ++status_.loops_received;
  worker_.Enqueue(msg, kLoopClosure, msg->header.seq);
}

template <class Pose>
bool VerifierNode<Pose>::OnSaveGraph(rrr_slam::SaveGraph::Request& req,
                                     rrr_slam::SaveGraph::Response& res) {
  worker_.RunOnWorker([&] {
    const rrr::OnlineVerifier<Pose>& verifier = session_.verifier();
    const auto& g = verifier.graph();
    if (g.num_poses() == 0) {
      res.success = false;
      res.message = "no keyframes yet";
      return;
    }
    SaveGraphFile(
        req.path,
        [&](std::ostream& out) {
          const std::vector<int> loops =
              req.with_candidates ? rrr::AllLoops(g) : verifier.AcceptedLoops();
          rrr::WriteG2o(g, session_.Map(), loops, out);
          if (!req.with_candidates) return;
          for (int c = 0; c < verifier.num_candidates(); ++c) {
            const auto [a, b] = verifier.ends_of(c);
            out << "# DECISION " << a << ' ' << b << ' '
                << rrr::ToString(verifier.state(c))
                << (verifier.loop_of(c) < 0 ? " waiting" : "") << '\n';
          }
        },
        &res);
  });
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
    const rrr::OnlineVerifier<Pose>& verifier = session_.verifier();
    std::vector<int> every(verifier.num_candidates());
    for (int c = 0; c < verifier.num_candidates(); ++c) every[c] = c;
    res.decisions = DecisionsMsg(verifier, every, {}, true, options_.map_frame);
  });
  return true;
}

template <class Pose>
bool VerifierNode<Pose>::OnGetAcceptedGraph(
    rrr_slam::GetAcceptedGraph::Request&,
    rrr_slam::GetAcceptedGraph::Response& res) {
  worker_.RunOnWorker([&] {
    res.graph = AcceptedGraphMsg(session_.verifier().graph(), session_.Map(),
                                 session_.verifier().AcceptedLoops(),
                                 options_.map_frame);
  });
  return true;
}

template <class Pose>
void VerifierNode<Pose>::OnTfTimer(const ros::TimerEvent&) {
  std::lock_guard<std::mutex> lock(status_.mutex);
  if (!have_map_to_odom_) return;
  // Stamped ahead so that lookups at the latest odometry time succeed.
  geometry_msgs::TransformStamped t = map_to_odom_;
  t.header.stamp = ros::Time::now() + ros::Duration(options_.tf_period);
  tf_broadcaster_.sendTransform(t);
}

// ---- Worker thread ---------------------------------------------------------

template <class Pose>
void VerifierNode<Pose>::Run() {
  worker_.Run(
      [this](const auto& msg, typename Worker::Clock::time_point arrival) {
        Process(msg);
        if constexpr (std::is_same_v<std::decay_t<decltype(msg)>,
                                     rrr_slam::LoopClosure::ConstPtr>) {
          status_.NoteCandidateArrival(arrival);
        }
        ++taken_since_update_;
      },
      [this] { UpdateAndPublish(false); });
}

template <class Pose>
void VerifierNode<Pose>::UpdateAndPublish(bool finish) {
  const auto start = std::chrono::steady_clock::now();
  const typename rrr::RobotSession<Pose>::Updated updated =
      session_.Update(finish);
  const std::vector<rrr::DecisionChange>& changes = updated.changes;
  status_.CountDatabaseError(updated.store_error);
  graph_stale_ = graph_stale_ || updated.accepted_changed || finish;
  const bool display_changed =
      updated.accepted_changed || !changes.empty() || new_keyframes_;
  path_stale_ = path_stale_ || display_changed;
  markers_stale_ = markers_stale_ || display_changed;
  new_keyframes_ = false;
  const rrr::OnlineVerifier<Pose>& verifier = session_.verifier();
  const std::vector<int> carried = decision_delta_.Next(verifier, changes);
  if (!carried.empty() || finish) {
    decision_pub_.publish(
        DecisionsMsg(verifier, carried, changes, false, options_.map_frame));
  }
  PublishDue(finish ? kAllOutputs : 0u);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();

  std::lock_guard<std::mutex> lock(status_.mutex);
  if (!session_.keyframes().empty()) {
    const Pose correction = session_.MapToOdom();
    map_to_odom_.header.frame_id = options_.map_frame;
    map_to_odom_.child_frame_id = options_.odom_frame;
    map_to_odom_.transform = ToRosTransform(correction);
    have_map_to_odom_ = true;
    geometry_msgs::TransformStamped t = map_to_odom_;
    t.header.stamp = ros::Time::now() + ros::Duration(options_.tf_period);
    tf_broadcaster_.sendTransform(t);
  }
  SetVerifierState(verifier, &status_.counts);
  status_.counts.waiting_by_stamp =
      static_cast<uint32_t>(session_.waiting_by_stamp());
  status_.counts.waiting += status_.counts.waiting_by_stamp;
  ++status_.counts.updates;
  status_.counts.inputs_processed += taken_since_update_;
  taken_since_update_ = 0;
  status_.timings.AddUpdate(seconds);
  status_.AddCandidateLatencies();
}

template <class Pose>
void VerifierNode<Pose>::PublishDue(unsigned now) {
  const ros::WallTime time = ros::WallTime::now();
  // Whether a message for `pub` (`output`), behind the state (`*stale`), is
  // due.
  auto due = [&](const ros::Publisher& pub, Output output, bool* stale,
                 ros::WallTime* last, double period) {
    if (!*stale || pub.getNumSubscribers() == 0) return false;
    if (!(now & output) && (time - *last).toSec() < period) return false;
    *stale = false;
    *last = time;
    return true;
  };
  if (due(path_pub_, kPath, &path_stale_, &last_path_,
          options_.display_period)) {
    path_pub_.publish(PathMsg(session_.Map(),
                              session_.keyframes().stamps().stamps(),
                              options_.map_frame));
  }
  if (due(marker_pub_, kMarkers, &markers_stale_, &last_markers_,
          options_.display_period)) {
    marker_pub_.publish(
        GraphMarkers(session_.verifier(), session_.Map(), options_.map_frame));
  }
  if (due(graph_pub_, kGraph, &graph_stale_, &last_graph_,
          options_.graph_period)) {
    graph_pub_.publish(AcceptedGraphMsg(
        session_.verifier().graph(), session_.Map(),
        session_.verifier().AcceptedLoops(), options_.map_frame));
  }
}

template class VerifierNode<rrr::Pose2>;
template class VerifierNode<rrr::Pose3>;

}  // namespace rrr_ros
