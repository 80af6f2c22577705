#include "graph_messages.h"

#include <cmath>
#include <fstream>
#include <map>
#include <utility>

#include "msg_conversion.h"
#include "rrr/io/g2o.h"

namespace rrr_ros {
namespace {

template <class Pose>
rrr_slam::GraphEdge EdgeMsg(const rrr::PoseGraph<Pose>& g,
                            const rrr::Constraint<Pose>& e) {
  rrr_slam::GraphEdge out;
  out.from_id = g.ids()[e.from];
  out.to_id = g.ids()[e.to];
  out.relative_pose = ToRos(e.measurement);
  for (int r = 0; r < Pose::kDof; ++r) {
    for (int c = 0; c < Pose::kDof; ++c)
      out.information.push_back(e.information(r, c));
  }
  return out;
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

// An empty marker of `type` in `frame`, namespace `ns`, id 0, coloured
// (r, g, b), its lines `width` wide.
visualization_msgs::Marker MakeMarker(const std::string& frame,
                                      const std::string& ns, int type, float r,
                                      float g, float b, double width) {
  visualization_msgs::Marker m;
  m.header.frame_id = frame;
  m.header.stamp = ros::Time::now();
  m.ns = ns;
  m.id = 0;
  m.type = type;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1.0;
  m.scale.x = width;
  m.scale.y = width;
  m.color.r = r;
  m.color.g = g;
  m.color.b = b;
  m.color.a = 1.0;
  return m;
}

// An empty LINE_LIST for candidates in `state`: green "accepted", red
// "rejected", yellow "pending".
visualization_msgs::Marker LoopMarker(const std::string& frame,
                                      rrr::LoopState state) {
  using visualization_msgs::Marker;
  switch (state) {
    case rrr::LoopState::kAccepted:
      return MakeMarker(frame, "accepted", Marker::LINE_LIST, 0.0f, 0.9f, 0.0f,
                        0.4);
    case rrr::LoopState::kRejected:
      return MakeMarker(frame, "rejected", Marker::LINE_LIST, 0.9f, 0.0f, 0.0f,
                        0.04);
    case rrr::LoopState::kPending:
      break;
  }
  return MakeMarker(frame, "pending", Marker::LINE_LIST, 1.0f, 0.85f, 0.0f,
                    0.06);
}

// A candidate's state as LoopDecision carries it.
uint8_t StateMsg(rrr::LoopState s) {
  switch (s) {
    case rrr::LoopState::kAccepted:
      return rrr_slam::LoopDecision::ACCEPTED;
    case rrr::LoopState::kRejected:
      return rrr_slam::LoopDecision::REJECTED;
    case rrr::LoopState::kPending:
      break;
  }
  return rrr_slam::LoopDecision::PENDING;
}

// Sets the reason fields of `d` from `reason`, decided as of keyframe
// `decided_at` (-1: not decided).
void SetReason(const rrr::DecisionReason& reason, int64_t decided_at,
               rrr_slam::LoopDecision* d) {
  d->test = rrr::ToString(reason.test);
  d->statistic = reason.statistic;
  d->gate = reason.gate;
  d->scale = reason.scale;
  d->dof = reason.dof;
  d->decided_at = decided_at;
  d->by_cluster = reason.by_cluster;
}

// Sets d->previous_state and d->reversed from `previous` (the states before
// the changes since the last message, by candidate; d->state set), and
// lists `d` in msg->changed if it changed; `d` is appended next.
void SetChange(const std::map<int, rrr::LoopState>& previous,
               rrr_slam::Decisions* msg, rrr_slam::LoopDecision* d) {
  const auto before = previous.find(static_cast<int>(d->candidate));
  d->previous_state =
      before == previous.end() ? d->state : StateMsg(before->second);
  d->reversed =
      before != previous.end() && before->second != rrr::LoopState::kPending;
  if (before != previous.end()) msg->changed.push_back(msg->decisions.size());
}

}  // namespace

template <class Pose>
rrr_slam::Decisions DecisionsMsg(
    const rrr::Session<Pose>& session, const std::vector<int>& carried,
    const std::vector<rrr::DecisionChange>& changes, bool full,
    const std::string& frame) {
  const rrr::OnlineVerifier<Pose>& verifier = session.verifier();
  rrr_slam::Decisions msg;
  msg.header.stamp = ros::Time::now();
  msg.header.frame_id = frame;
  msg.full = full;
  // The state each changed candidate had before the first of `changes`.
  std::map<int, rrr::LoopState> previous;
  for (const auto& c : changes) previous.emplace(c.candidate, c.previous);
  msg.decisions.reserve(carried.size());
  for (const int c : carried) {
    rrr_slam::LoopDecision d;
    d.candidate = c;
    const rrr::ChainPose from = session.from(c), to = session.to(c);
    d.from_robot = session.robots()[session.robot_of_chain(from.chain)];
    d.to_robot = session.robots()[session.robot_of_chain(to.chain)];
    d.from_id = from.id;
    d.to_id = to.id;
    d.state = StateMsg(verifier.state(c));
    d.cluster = verifier.cluster_of(c);
    d.waiting = verifier.loop_of(c) < 0;
    SetReason(verifier.reason(c), session.DecidedAt(c), &d);
    SetChange(previous, &msg, &d);
    msg.decisions.push_back(d);
  }
  msg.candidates = verifier.num_candidates();
  msg.accepted = verifier.num_in_state(rrr::LoopState::kAccepted);
  msg.rejected = verifier.num_in_state(rrr::LoopState::kRejected);
  msg.pending = verifier.num_in_state(rrr::LoopState::kPending);
  return msg;
}

template <class Pose>
nav_msgs::Path PathMsg(rrr::Session<Pose>& session, int robot,
                       const std::string& frame) {
  const int map = session.MapOfRobot(robot);
  const std::vector<Pose> poses = session.Path(robot, map);
  const std::vector<std::int64_t> stamps = session.PathStamps(robot, map);
  nav_msgs::Path path;
  path.header.stamp =
      stamps.empty() ? ros::Time::now() : ros::Time().fromNSec(stamps.back());
  path.header.frame_id = frame;
  for (size_t k = 0; k < poses.size(); ++k) {
    geometry_msgs::PoseStamped p;
    p.header.stamp.fromNSec(stamps[k]);
    p.header.frame_id = frame;
    p.pose = ToRos(poses[k]);
    path.poses.push_back(p);
  }
  return path;
}

template <class Pose>
visualization_msgs::MarkerArray GraphMarkers(rrr::Session<Pose>& session,
                                             const MapFrames& frames) {
  using visualization_msgs::Marker;
  visualization_msgs::MarkerArray array;
  const int robots = static_cast<int>(session.robots().size());
  for (int r = 0; r < robots; ++r) {
    const int map = session.MapOfRobot(r);
    if (map < 0) continue;
    Marker path =
        MakeMarker(frames(map), robots == 1 ? "odometry" : session.robots()[r],
                   Marker::LINE_STRIP, 0.2f, 0.4f, 1.0f, 0.05);
    if (robots > 1) path.color = RobotColour(r);
    for (const Pose& p : session.Path(r, map)) {
      path.points.push_back(ToRos(p).position);
    }
    array.markers.push_back(path);
  }
  // Loops whose two ends are in one map, by map (its lowest chain) and
  // state; a chain that is no map (any more) deletes what it showed.
  std::map<std::pair<int, rrr::LoopState>, Marker> loops;
  for (int c = 0; c < session.num_chains(); ++c) {
    for (const rrr::LoopState state :
         {rrr::LoopState::kAccepted, rrr::LoopState::kRejected,
          rrr::LoopState::kPending}) {
      Marker& marker = loops[{c, state}] = LoopMarker(frames(c), state);
      marker.id = c;
    }
  }
  const rrr::OnlineVerifier<Pose>& verifier = session.verifier();
  for (int c = 0; c < verifier.num_candidates(); ++c) {
    const rrr::ChainPose a = session.from(c), b = session.to(c);
    const int map = session.MapOfChain(a.chain);
    const auto pa = session.Corrected(a), pb = session.Corrected(b);
    if (map != session.MapOfChain(b.chain) || !pa || !pb) continue;
    Marker& marker = loops[{map, verifier.state(c)}];
    marker.points.push_back(ToRos(*pa).position);
    marker.points.push_back(ToRos(*pb).position);
  }
  for (auto& [key, marker] : loops) {
    if (marker.points.empty()) marker.action = Marker::DELETE;
    array.markers.push_back(marker);
  }
  return array;
}

template <class Pose>
rrr_slam::AcceptedGraph AcceptedGraphMsg(rrr::Session<Pose>& session, int map,
                                         const std::string& frame) {
  rrr_slam::AcceptedGraph msg;
  msg.header.stamp = ros::Time::now();
  msg.header.frame_id = frame;
  if (map < 0) return msg;
  const typename rrr::Session<Pose>::MapGraph accepted =
      session.AcceptedGraph(map);
  const rrr::PoseGraph<Pose>& graph = accepted.graph;
  msg.ids = graph.ids();
  for (const Pose& p : graph.estimates()) msg.poses.push_back(ToRos(p));
  for (const auto& e : graph.odometry()) {
    msg.odometry.push_back(EdgeMsg(graph, e));
  }
  for (const auto& e : graph.loops()) msg.loops.push_back(EdgeMsg(graph, e));
  msg.keyframe_ids = accepted.keyframe;
  if (session.robots().size() > 1) {
    for (const int r : accepted.robot) {
      msg.robots.push_back(session.robots()[r]);
    }
  }
  return msg;
}

template <class Pose>
void SaveGraphFile(rrr::Session<Pose>& session, const std::string& path,
                   bool with_candidates, rrr_slam::SaveGraph::Response* res) {
  const rrr::OnlineVerifier<Pose>& verifier = session.verifier();
  std::vector<int> candidate_of_loop;
  const rrr::PoseGraph<Pose> graph = session.Graph(&candidate_of_loop);
  res->success = false;
  if (graph.num_poses() == 0) {
    res->message = "no keyframes yet";
    return;
  }
  std::ofstream out(path);
  if (!out) {
    res->message = "cannot open " + path + " for writing";
    return;
  }
  std::vector<int> loops;
  for (size_t k = 0; k < candidate_of_loop.size(); ++k) {
    if (with_candidates ||
        verifier.state(candidate_of_loop[k]) == rrr::LoopState::kAccepted) {
      loops.push_back(static_cast<int>(k));
    }
  }
  rrr::WriteG2o(graph, graph.estimates(), loops, out);
  const auto name = [&](const rrr::ChainPose& p) {
    const std::string& robot =
        session.robots()[session.robot_of_chain(p.chain)];
    return (robot.empty() ? "" : robot + ":") + std::to_string(p.id);
  };
  for (int c = 0; with_candidates && c < verifier.num_candidates(); ++c) {
    out << "# DECISION " << name(session.from(c)) << ' ' << name(session.to(c))
        << ' ' << rrr::ToString(verifier.state(c))
        << (verifier.loop_of(c) < 0 ? " waiting" : "") << '\n';
  }
  out.close();
  res->success = static_cast<bool>(out);
  res->message = res->success ? "wrote " + path : "write failed: " + path;
}

#define RRR_INSTANTIATE_GRAPH_MESSAGES(Pose)                                  \
  template rrr_slam::Decisions DecisionsMsg(                                  \
      const rrr::Session<Pose>&, const std::vector<int>&,                     \
      const std::vector<rrr::DecisionChange>&, bool, const std::string&);     \
  template nav_msgs::Path PathMsg(rrr::Session<Pose>&, int,                   \
                                  const std::string&);                        \
  template visualization_msgs::MarkerArray GraphMarkers(rrr::Session<Pose>&,  \
                                                        const MapFrames&);    \
  template rrr_slam::AcceptedGraph AcceptedGraphMsg(rrr::Session<Pose>&, int, \
                                                    const std::string&);      \
  template void SaveGraphFile(rrr::Session<Pose>&, const std::string&, bool,  \
                              rrr_slam::SaveGraph::Response*);
RRR_INSTANTIATE_GRAPH_MESSAGES(rrr::Pose2)
RRR_INSTANTIATE_GRAPH_MESSAGES(rrr::Pose3)
#undef RRR_INSTANTIATE_GRAPH_MESSAGES

}  // namespace rrr_ros
