#include "fleet_node.h"

#include <nav_msgs/Path.h>
#include <visualization_msgs/MarkerArray.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <map>
#include <mutex>
#include <numeric>
#include <type_traits>

#include "graph_messages.h"
#include "msg_conversion.h"
#include "rrr/io/g2o.h"
#include "rrr_slam/Keyframe.h"
#include "status_messages.h"

namespace rrr_ros {
namespace {

constexpr int kQueueSize = 10000;  // ROS subscriber queues

rrr::FleetOptions FleetOptionsOf(const NodeOptions& options) {
  rrr::FleetOptions fleet;
  fleet.rrr = options.rrr;
  fleet.odometry = options.odometry;
  fleet.restart_jump = options.restart_jump;
  // An update must not wait for the loops between robots to be judged
  // again over the whole graph.
  return fleet;
}

// A colour per robot, apart around the hue circle.
std_msgs::ColorRGBA RobotColour(int robot) {
  const double hue = std::fmod(0.13 + 0.381966 * robot, 1.0) * 6.0;
  const double x = 1.0 - std::abs(std::fmod(hue, 2.0) - 1.0);
  const int sector = static_cast<int>(hue);
  const double rgb[6][3] = {{1, x, 0}, {x, 1, 0}, {0, 1, x},
                            {0, x, 1}, {x, 0, 1}, {1, 0, x}};
  std_msgs::ColorRGBA colour;
  colour.r = static_cast<float>(0.2 + 0.8 * rgb[sector][0]);
  colour.g = static_cast<float>(0.2 + 0.8 * rgb[sector][1]);
  colour.b = static_cast<float>(0.2 + 0.8 * rgb[sector][2]);
  colour.a = 1.0f;
  return colour;
}

}  // namespace

template <class Pose>
FleetNode<Pose>::FleetNode(ros::NodeHandle& nh, ros::NodeHandle& private_nh,
                           const NodeOptions& options)
    : options_(options),
      nh_(nh),
      private_nh_(private_nh),
      worker_(options.max_queue_length),
      session_(options.robots, FleetOptionsOf(options), options.database) {
  status_.counts.procedure = rrr::ToString(options_.rrr.procedure);
  if (!options_.database.empty()) Resume();
  const int robots = static_cast<int>(options_.robots.size());
  map_to_odom_.resize(robots);
  for (int r = 0; r < robots; ++r) {
    const std::string& name = options_.robots[r];
    keyframe_pubs_.push_back(
        private_nh_.advertise<rrr_slam::Keyframe>(name + "/keyframes", 1000));
    path_pubs_.push_back(
        private_nh_.advertise<nav_msgs::Path>(name + "/path", 1, true));
  }
  marker_pub_ =
      private_nh_.advertise<visualization_msgs::MarkerArray>("graph", 1, true);
  graph_pub_ =
      private_nh_.advertise<rrr_slam::AcceptedGraph>("accepted_graph", 1, true);
  graph_srv_ = private_nh_.advertiseService(
      "get_accepted_graph", &FleetNode::OnGetAcceptedGraph, this);
  decision_pub_ =
      private_nh_.advertise<rrr_slam::Decisions>("decisions", 100, true);
  decisions_srv_ = private_nh_.advertiseService(
      "get_decisions", &FleetNode::OnGetDecisions, this);
  finish_srv_ =
      private_nh_.advertiseService("finish", &FleetNode::OnFinish, this);
  save_srv_ =
      private_nh_.advertiseService("save_graph", &FleetNode::OnSaveGraph, this);
  tf_timer_ = nh_.createTimer(ros::Duration(options_.tf_period),
                              &FleetNode::OnTfTimer, this);
  for (int r = 0; r < robots; ++r) {
    odom_subs_.push_back(nh_.subscribe<nav_msgs::Odometry>(
        options_.robots[r] + "/odom", kQueueSize,
        [this, r](const nav_msgs::Odometry::ConstPtr& msg) {
          ++status_.odometry_received;
          worker_.Enqueue(RobotOdometry{r, msg}, "odometry", msg->header.seq);
        },
        ros::VoidConstPtr(), ros::TransportHints().tcpNoDelay()));
  }
  fleet_loop_sub_ = nh_.subscribe<rrr_slam::FleetLoopClosure>(
      "fleet_loop_closures", kQueueSize,
      [this](const rrr_slam::FleetLoopClosure::ConstPtr& msg) {
        ++status_.loops_received;
        worker_.Enqueue(msg, "fleet loop closure", msg->loop.header.seq);
      },
      ros::VoidConstPtr(), ros::TransportHints().tcpNoDelay());
  loop_sub_ = nh_.subscribe<rrr_slam::LoopClosure>(
      "loop_closures", kQueueSize,
      [this](const rrr_slam::LoopClosure::ConstPtr& msg) {
        ++status_.loops_received;
        worker_.Enqueue(msg, "loop closure", msg->header.seq);
      },
      ros::VoidConstPtr(), ros::TransportHints().tcpNoDelay());
  status_.Serve(nh_, private_nh_, [this](rrr_slam::GetStatus::Response* s) {
    worker_.SetQueueStatus(s);
  });
}

template <class Pose>
FleetNode<Pose>::~FleetNode() {
  for (ros::Subscriber& sub : odom_subs_) sub.shutdown();
  fleet_loop_sub_.shutdown();
  loop_sub_.shutdown();
  worker_.Stop();
}

template <class Pose>
void FleetNode<Pose>::Stop() {
  worker_.Stop();
}

template <class Pose>
void FleetNode<Pose>::Resume() {
  const rrr::FleetResumeSummary summary = status_.CountResumed(
      options_.database, [&] { return session_.Resume(); },
      "were the options changed, or loops between robots judged at another "
      "update?");
  CountState();
  changed_ = summary.keyframes > 0;
  ROS_INFO(
      "rrr_node: fleet session %s: resumed %d keyframes in %d sessions, %d "
      "candidates, %d updates; each robot continues in a new session",
      options_.database.c_str(), summary.keyframes, summary.sessions,
      summary.candidates, summary.updates);
}

template <class Pose>
std::string FleetNode<Pose>::RobotFrame(int robot,
                                        const std::string& frame) const {
  return options_.robots[robot] + "/" + frame;
}

template <class Pose>
std::string FleetNode<Pose>::MapFrame(int map) const {
  if (map == session_.fleet().MapOfChain(0)) return options_.map_frame;
  const int robot = session_.fleet().robot_of_chain(map);
  const std::vector<int>& sessions = session_.fleet().sessions(robot);
  const auto k =
      std::find(sessions.begin(), sessions.end(), map) - sessions.begin();
  return RobotFrame(robot, k == 0 ? "map" : "map_" + std::to_string(k));
}

// ---- ROS threads ----------------------------------------------------------

template <class Pose>
bool FleetNode<Pose>::OnFinish(rrr_slam::Finish::Request&,
                               rrr_slam::Finish::Response& res) {
  worker_.RunOnWorker([&] {
    UpdateAndPublish(true);
    const auto& v = session_.fleet().verifier();
    res.accepted = v.num_in_state(rrr::LoopState::kAccepted);
    res.rejected = v.num_in_state(rrr::LoopState::kRejected);
    res.pending = v.num_in_state(rrr::LoopState::kPending);
    res.waiting =
        static_cast<uint32_t>(session_.fleet().num_waiting_for_robots());
  });
  return true;
}

template <class Pose>
bool FleetNode<Pose>::OnSaveGraph(rrr_slam::SaveGraph::Request& req,
                                  rrr_slam::SaveGraph::Response& res) {
  worker_.RunOnWorker([&] {
    const auto& v = session_.fleet().verifier();
    std::vector<int> candidate_of_loop;
    const rrr::PoseGraph<Pose> graph =
        session_.fleet().Graph(&candidate_of_loop);
    if (graph.num_poses() == 0) {
      res.success = false;
      res.message = "no keyframes yet";
      return;
    }
    SaveGraphFile(
        req.path,
        [&](std::ostream& out) {
          std::vector<int> loops;
          for (size_t k = 0; k < candidate_of_loop.size(); ++k) {
            if (req.with_candidates ||
                v.state(candidate_of_loop[k]) == rrr::LoopState::kAccepted) {
              loops.push_back(static_cast<int>(k));
            }
          }
          rrr::WriteG2o(graph, graph.estimates(), loops, out);
          if (!req.with_candidates) return;
          const auto name = [&](const rrr::ChainPose& p) {
            return options_.robots[session_.fleet().robot_of_chain(p.chain)] +
                   ":" + std::to_string(p.id);
          };
          for (const int k : loops) {
            const int c = candidate_of_loop[k];
            out << "# DECISION " << name(session_.fleet().from(c)) << ' '
                << name(session_.fleet().to(c)) << ' '
                << rrr::ToString(v.state(c)) << '\n';
          }
        },
        &res);
  });
  return true;
}

template <class Pose>
bool FleetNode<Pose>::OnGetAcceptedGraph(
    rrr_slam::GetAcceptedGraph::Request&,
    rrr_slam::GetAcceptedGraph::Response& res) {
  worker_.RunOnWorker([&] { res.graph = AcceptedGraph(); });
  return true;
}

template <class Pose>
bool FleetNode<Pose>::OnGetDecisions(rrr_slam::GetDecisions::Request&,
                                     rrr_slam::GetDecisions::Response& res) {
  worker_.RunOnWorker([&] {
    std::vector<int> every(session_.fleet().verifier().num_candidates());
    for (size_t c = 0; c < every.size(); ++c) every[c] = static_cast<int>(c);
    res.decisions = DecisionsMsg(every, {}, true);
  });
  return true;
}

template <class Pose>
rrr_slam::Decisions FleetNode<Pose>::DecisionsMsg(
    const std::vector<int>& carried,
    const std::vector<rrr::DecisionChange>& changes, bool full) const {
  const auto& v = session_.fleet().verifier();
  rrr_slam::Decisions msg;
  msg.header.stamp = ros::Time::now();
  msg.header.frame_id = options_.map_frame;
  msg.full = full;
  std::map<int, rrr::LoopState> previous;
  for (const auto& c : changes) previous.emplace(c.candidate, c.previous);
  for (const int c : carried) {
    rrr_slam::LoopDecision d;
    d.candidate = c;
    d.from_robot = options_.robots[session_.fleet().robot_of_chain(
        session_.fleet().from(c).chain)];
    d.to_robot = options_.robots[session_.fleet().robot_of_chain(
        session_.fleet().to(c).chain)];
    d.from_id = session_.fleet().from(c).id;
    d.to_id = session_.fleet().to(c).id;
    d.state = StateMsg(v.state(c));
    d.cluster = v.cluster_of(c);
    d.waiting = v.waiting(c);
    SetReason(v.reason(c), session_.fleet().DecidedAt(c), &d);
    SetChange(previous, &msg, &d);
    msg.decisions.push_back(d);
  }
  msg.candidates = static_cast<uint32_t>(v.num_candidates());
  msg.accepted =
      static_cast<uint32_t>(v.num_in_state(rrr::LoopState::kAccepted));
  msg.rejected =
      static_cast<uint32_t>(v.num_in_state(rrr::LoopState::kRejected));
  msg.pending = static_cast<uint32_t>(v.num_in_state(rrr::LoopState::kPending));
  return msg;
}

template <class Pose>
void FleetNode<Pose>::OnTfTimer(const ros::TimerEvent&) {
  std::lock_guard<std::mutex> lock(status_.mutex);
  const ros::Time stamp = ros::Time::now() + ros::Duration(options_.tf_period);
  for (geometry_msgs::TransformStamped t : map_to_odom_) {
    if (t.child_frame_id.empty()) continue;  // no keyframe yet
    t.header.stamp = stamp;
    tf_broadcaster_.sendTransform(t);
  }
}

// ---- Worker thread ---------------------------------------------------------

template <class Pose>
void FleetNode<Pose>::Run() {
  worker_.Run(
      [this](const auto& message, typename Worker::Clock::time_point arrival) {
        Process(message);
        if constexpr (!std::is_same_v<std::decay_t<decltype(message)>,
                                      RobotOdometry>) {
          status_.NoteCandidateArrival(arrival);
        }
        ++taken_since_update_;
      },
      [this] { UpdateAndPublish(false); });
}

template <class Pose>
void FleetNode<Pose>::UpdateAndPublish(bool finish) {
  const auto start = std::chrono::steady_clock::now();
  const typename rrr::FleetSession<Pose>::Updated updated =
      session_.Update(finish);
  const std::vector<rrr::DecisionChange>& changes = updated.changes;
  status_.CountDatabaseError(updated.store_error);
  changed_ = changed_ || !changes.empty() || finish;
  // ~decisions: the candidates new, changed, or clustered or no longer
  // waiting since the last message.
  const std::vector<int> carried =
      decision_delta_.Next(session_.fleet().verifier(), changes);
  if (!carried.empty() || finish) {
    decision_pub_.publish(DecisionsMsg(carried, changes, false));
  }
  const ros::WallTime now = ros::WallTime::now();
  if (changed_ &&
      (finish || (now - last_published_).toSec() >= options_.display_period)) {
    changed_ = false;
    last_published_ = now;
    using visualization_msgs::Marker;
    visualization_msgs::MarkerArray markers;
    for (int r = 0; r < static_cast<int>(options_.robots.size()); ++r) {
      const int map = session_.fleet().MapOfRobot(r);
      if (map < 0) continue;
      const std::string frame = MapFrame(map);
      path_pubs_[r].publish(PathMsg(session_.fleet().Path(r, map),
                                    session_.fleet().PathStamps(r, map),
                                    frame));
      Marker path = MakeMarker(frame, options_.robots[r], Marker::LINE_STRIP,
                               0.0f, 0.0f, 0.0f, 0.05);
      path.color = RobotColour(r);
      for (const Pose& p : session_.fleet().Path(r, map)) {
        path.points.push_back(ToRos(p).position);
      }
      markers.markers.push_back(path);
    }
    // Loops whose two ends are in one map, by state.
    const auto& v = session_.fleet().verifier();
    std::map<std::pair<int, rrr::LoopState>, Marker> loops;
    for (int c = 0; c < v.num_candidates(); ++c) {
      const rrr::ChainPose a = session_.fleet().from(c),
                           b = session_.fleet().to(c);
      const int map = session_.fleet().MapOfChain(a.chain);
      const auto pa = session_.fleet().Corrected(a),
                 pb = session_.fleet().Corrected(b);
      if (map != session_.fleet().MapOfChain(b.chain) || !pa || !pb) continue;
      auto [it, added] = loops.try_emplace({map, v.state(c)});
      if (added) {
        it->second = LoopMarker(MapFrame(map), v.state(c));
        it->second.id = map;
      }
      it->second.points.push_back(ToRos(*pa).position);
      it->second.points.push_back(ToRos(*pb).position);
    }
    for (auto& [key, marker] : loops) markers.markers.push_back(marker);
    marker_pub_.publish(markers);
    // The accepted graph copies the whole fleet's graph: only for listeners.
    if (graph_pub_.getNumSubscribers() > 0 &&
        (finish ||
         (now - last_graph_published_).toSec() >= options_.graph_period)) {
      last_graph_published_ = now;
      graph_pub_.publish(AcceptedGraph());
    }
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();

  std::lock_guard<std::mutex> lock(status_.mutex);
  for (int r = 0; r < static_cast<int>(options_.robots.size()); ++r) {
    const std::optional<Pose> correction = session_.fleet().MapToOdom(r);
    if (!correction) continue;
    geometry_msgs::TransformStamped& t = map_to_odom_[r];
    t.header.frame_id = MapFrame(session_.fleet().MapOfRobot(r));
    t.child_frame_id = RobotFrame(r, options_.odom_frame);
    t.transform = ToRosTransform(*correction);
    t.header.stamp = ros::Time::now() + ros::Duration(options_.tf_period);
    tf_broadcaster_.sendTransform(t);
  }
  CountState();
  ++status_.counts.updates;
  status_.counts.inputs_processed += taken_since_update_;
  taken_since_update_ = 0;
  status_.timings.AddUpdate(seconds);
  status_.AddCandidateLatencies();
}

template <class Pose>
rrr_slam::AcceptedGraph FleetNode<Pose>::AcceptedGraph() const {
  const rrr::FleetGraph<Pose> accepted = session_.fleet().AcceptedGraph(
      session_.fleet().num_chains() > 0 ? session_.fleet().MapOfChain(0) : -1);
  std::vector<int> loops(accepted.graph.loops().size());
  std::iota(loops.begin(), loops.end(), 0);
  rrr_slam::AcceptedGraph msg = AcceptedGraphMsg(
      accepted.graph, accepted.graph.estimates(), loops, options_.map_frame);
  for (size_t k = 0; k < accepted.robot.size(); ++k) {
    msg.robots.push_back(options_.robots[accepted.robot[k]]);
    msg.keyframe_ids.push_back(accepted.keyframe[k]);
  }
  return msg;
}

template <class Pose>
void FleetNode<Pose>::CountState() {
  const auto& v = session_.fleet().verifier();
  status_.counts.candidates = static_cast<uint32_t>(v.num_candidates());
  status_.counts.accepted =
      static_cast<uint32_t>(v.num_in_state(rrr::LoopState::kAccepted));
  status_.counts.rejected =
      static_cast<uint32_t>(v.num_in_state(rrr::LoopState::kRejected));
  status_.counts.pending =
      static_cast<uint32_t>(v.num_in_state(rrr::LoopState::kPending));
  status_.counts.waiting =
      static_cast<uint32_t>(session_.fleet().num_waiting_for_robots());
  status_.counts.waiting_by_stamp =
      static_cast<uint32_t>(session_.fleet().num_waiting_by_stamp());
  // Candidates by stamp refused once their keyframes came: none near.
  status_.counts.skipped_unknown_poses += static_cast<uint64_t>(
      session_.fleet().refused_by_stamp() - refused_by_stamp_counted_);
  refused_by_stamp_counted_ = session_.fleet().refused_by_stamp();
  status_.counts.keyframes = 0;
  for (int c = 0; c < session_.fleet().num_chains(); ++c) {
    status_.counts.keyframes +=
        static_cast<uint32_t>(session_.fleet().ChainSize(c));
  }
}

template class FleetNode<rrr::Pose2>;
template class FleetNode<rrr::Pose3>;

}  // namespace rrr_ros
