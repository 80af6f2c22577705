#include "graph_messages.h"

#include <fstream>
#include <map>

#include "msg_conversion.h"

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

}  // namespace

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

void SetChange(const std::map<int, rrr::LoopState>& previous,
               rrr_slam::Decisions* msg, rrr_slam::LoopDecision* d) {
  const auto before = previous.find(static_cast<int>(d->candidate));
  d->previous_state =
      before == previous.end() ? d->state : StateMsg(before->second);
  d->reversed =
      before != previous.end() && before->second != rrr::LoopState::kPending;
  if (before != previous.end()) msg->changed.push_back(msg->decisions.size());
}

template <class Pose>
rrr_slam::Decisions DecisionsMsg(
    const rrr::OnlineVerifier<Pose>& verifier, const std::vector<int>& carried,
    const std::vector<rrr::DecisionChange>& changes, bool full,
    const std::string& frame) {
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
    std::tie(d.from_id, d.to_id) = verifier.ends_of(c);
    d.state = StateMsg(verifier.state(c));
    d.cluster = verifier.cluster_of(c);
    d.waiting = verifier.loop_of(c) < 0;
    const rrr::DecisionReason reason = verifier.reason(c);
    SetReason(reason,
              reason.pose < 0 ? -1 : verifier.graph().ids()[reason.pose], &d);
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
nav_msgs::Path PathMsg(const std::vector<Pose>& map,
                       const std::vector<std::int64_t>& stamps_ns,
                       const std::string& frame) {
  nav_msgs::Path path;
  path.header.stamp = stamps_ns.empty()
                          ? ros::Time::now()
                          : ros::Time().fromNSec(stamps_ns.back());
  path.header.frame_id = frame;
  for (size_t k = 0; k < map.size(); ++k) {
    geometry_msgs::PoseStamped p;
    p.header.stamp.fromNSec(stamps_ns[k]);
    p.header.frame_id = frame;
    p.pose = ToRos(map[k]);
    path.poses.push_back(p);
  }
  return path;
}

template <class Pose>
visualization_msgs::MarkerArray GraphMarkers(
    const rrr::OnlineVerifier<Pose>& verifier, const std::vector<Pose>& map,
    const std::string& frame) {
  using visualization_msgs::Marker;
  auto odometry =
      MakeMarker(frame, "odometry", Marker::LINE_STRIP, 0.2f, 0.4f, 1.0f, 0.05);
  auto poses =
      MakeMarker(frame, "poses", Marker::POINTS, 0.1f, 0.1f, 0.6f, 0.08);
  auto accepted = LoopMarker(frame, rrr::LoopState::kAccepted);
  auto rejected = LoopMarker(frame, rrr::LoopState::kRejected);
  auto pending = LoopMarker(frame, rrr::LoopState::kPending);
  for (const Pose& p : map) {
    odometry.points.push_back(ToRos(p).position);
    poses.points.push_back(ToRos(p).position);
  }
  const auto& graph = verifier.graph();
  for (int c = 0; c < verifier.num_candidates(); ++c) {
    const int loop = verifier.loop_of(c);
    if (loop < 0) continue;
    const auto& e = graph.loops()[loop];
    auto& list = verifier.state(c) == rrr::LoopState::kAccepted   ? accepted
                 : verifier.state(c) == rrr::LoopState::kRejected ? rejected
                                                                  : pending;
    list.points.push_back(ToRos(map[e.from]).position);
    list.points.push_back(ToRos(map[e.to]).position);
  }
  visualization_msgs::MarkerArray array;
  for (auto* m : {&odometry, &poses, &accepted, &rejected, &pending}) {
    if (m->points.empty()) m->action = Marker::DELETE;
    array.markers.push_back(*m);
  }
  return array;
}

template <class Pose>
rrr_slam::AcceptedGraph AcceptedGraphMsg(const rrr::PoseGraph<Pose>& graph,
                                         const std::vector<Pose>& map,
                                         const std::vector<int>& accepted,
                                         const std::string& frame) {
  rrr_slam::AcceptedGraph msg;
  msg.header.stamp = ros::Time::now();
  msg.header.frame_id = frame;
  msg.ids = graph.ids();
  for (const Pose& p : map) msg.poses.push_back(ToRos(p));
  for (const auto& e : graph.odometry())
    msg.odometry.push_back(EdgeMsg(graph, e));
  for (const int k : accepted)
    msg.loops.push_back(EdgeMsg(graph, graph.loops()[k]));
  return msg;
}

void SaveGraphFile(const std::string& path,
                   const std::function<void(std::ostream&)>& write,
                   rrr_slam::SaveGraph::Response* res) {
  std::ofstream out(path);
  if (!out) {
    res->success = false;
    res->message = "cannot open " + path + " for writing";
    return;
  }
  write(out);
  out.close();
  res->success = static_cast<bool>(out);
  res->message = res->success ? "wrote " + path : "write failed: " + path;
}

#define RRR_INSTANTIATE_GRAPH_MESSAGES(Pose)                              \
  template rrr_slam::Decisions DecisionsMsg(                              \
      const rrr::OnlineVerifier<Pose>&, const std::vector<int>&,          \
      const std::vector<rrr::DecisionChange>&, bool, const std::string&); \
  template nav_msgs::Path PathMsg(const std::vector<Pose>&,               \
                                  const std::vector<std::int64_t>&,       \
                                  const std::string&);                    \
  template visualization_msgs::MarkerArray GraphMarkers(                  \
      const rrr::OnlineVerifier<Pose>&, const std::vector<Pose>&,         \
      const std::string&);                                                \
  template rrr_slam::AcceptedGraph AcceptedGraphMsg(                      \
      const rrr::PoseGraph<Pose>&, const std::vector<Pose>&,              \
      const std::vector<int>&, const std::string&);
RRR_INSTANTIATE_GRAPH_MESSAGES(rrr::Pose2)
RRR_INSTANTIATE_GRAPH_MESSAGES(rrr::Pose3)
#undef RRR_INSTANTIATE_GRAPH_MESSAGES

}  // namespace rrr_ros
