// The messages rrr_node publishes about its graph, built from the verifier's
// state and the map (keyframe poses in the map frame). Pure functions of
// their arguments: no ROS communication here.
#ifndef RRR_ROS_GRAPH_MESSAGES_H_
#define RRR_ROS_GRAPH_MESSAGES_H_

#include <nav_msgs/Path.h>
#include <visualization_msgs/MarkerArray.h>

#include <cstdint>
#include <functional>
#include <map>
#include <ostream>
#include <string>
#include <vector>

#include "rrr/rrr/online_verifier.h"
#include "rrr_slam/AcceptedGraph.h"
#include "rrr_slam/Decisions.h"
#include "rrr_slam/SaveGraph.h"

namespace rrr_ros {

// An empty marker of `type` in `frame`, namespace `ns`, id 0, coloured
// (r, g, b), its lines `width` wide.
visualization_msgs::Marker MakeMarker(const std::string& frame,
                                      const std::string& ns, int type, float r,
                                      float g, float b, double width);
// An empty LINE_LIST for candidates in `state`: green "accepted", red
// "rejected", yellow "pending".
visualization_msgs::Marker LoopMarker(const std::string& frame,
                                      rrr::LoopState state);

// A candidate's state as LoopDecision carries it.
uint8_t StateMsg(rrr::LoopState state);
// Sets the reason fields of `d` from `reason`, decided as of keyframe
// `decided_at` (-1: not decided).
void SetReason(const rrr::DecisionReason& reason, int64_t decided_at,
               rrr_slam::LoopDecision* d);
// Sets d->previous_state and d->reversed from `previous` (the states before
// the changes since the last message, by candidate; d->state set), and
// lists `d` in msg->changed if it changed; `d` is appended next.
void SetChange(const std::map<int, rrr::LoopState>& previous,
               rrr_slam::Decisions* msg, rrr_slam::LoopDecision* d);

// The state now of the candidates `carried` (ascending candidate numbers),
// with `changes` (the updates' since the last message) marked as changed
// and, when they left a decided state, as reversed; `full` says that
// `carried` is every candidate. The counts are over every candidate.
template <class Pose>
rrr_slam::Decisions DecisionsMsg(
    const rrr::OnlineVerifier<Pose>& verifier, const std::vector<int>& carried,
    const std::vector<rrr::DecisionChange>& changes, bool full,
    const std::string& frame);

// The map as a path: one pose per keyframe, stamped with its keyframe's
// stamp (`stamps_ns`, nanoseconds, has one per pose of `map`).
template <class Pose>
nav_msgs::Path PathMsg(const std::vector<Pose>& map,
                       const std::vector<std::int64_t>& stamps_ns,
                       const std::string& frame);

// rviz markers: the odometry chain and poses of `map`, and each candidate
// whose poses exist as a line, green if accepted, red if rejected, yellow if
// pending. An empty list is sent as DELETE, which clears an old one.
template <class Pose>
visualization_msgs::MarkerArray GraphMarkers(
    const rrr::OnlineVerifier<Pose>& verifier, const std::vector<Pose>& map,
    const std::string& frame);

// The accepted graph: `graph`'s ids with `map` as their poses, every
// odometry edge and the loops `accepted` (graph loop indices).
template <class Pose>
rrr_slam::AcceptedGraph AcceptedGraphMsg(const rrr::PoseGraph<Pose>& graph,
                                         const std::vector<Pose>& map,
                                         const std::vector<int>& accepted,
                                         const std::string& frame);

// Writes a graph file at `path` with `write` and says in `*res` whether it
// was written (naming the path), as ~save_graph answers.
void SaveGraphFile(const std::string& path,
                   const std::function<void(std::ostream&)>& write,
                   rrr_slam::SaveGraph::Response* res);

}  // namespace rrr_ros

#endif  // RRR_ROS_GRAPH_MESSAGES_H_
