// The messages rrr_node publishes about its graph, built from the session's
// state (the corrected keyframe poses and the decisions). Pure functions of
// their arguments: no ROS communication here.
#ifndef RRR_ROS_GRAPH_MESSAGES_H_
#define RRR_ROS_GRAPH_MESSAGES_H_

#include <nav_msgs/Path.h>
#include <visualization_msgs/MarkerArray.h>

#include <cstdint>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include "rrr/session/session.h"
#include "rrr_slam/AcceptedGraph.h"
#include "rrr_slam/Decisions.h"
#include "rrr_slam/SaveGraph.h"

namespace rrr_ros {

// The frame of each map (a chain index: Session::MapOfChain).
using MapFrames = std::function<std::string(int map)>;

// The state now of the candidates `carried` (ascending candidate numbers),
// with `changes` (the updates' since the last message) marked as changed
// and, when they left a decided state, as reversed; `full` says that
// `carried` is every candidate. The counts are over every candidate.
template <class Pose>
rrr_slam::Decisions DecisionsMsg(
    const rrr::Session<Pose>& session, const std::vector<int>& carried,
    const std::vector<rrr::DecisionChange>& changes, bool full,
    const std::string& frame);

// Robot `robot`'s sessions in the map of its current one as a path: one
// pose per keyframe, stamped with its keyframe's stamp.
template <class Pose>
nav_msgs::Path PathMsg(rrr::Session<Pose>& session, int robot,
                       const std::string& frame);

// rviz markers, each in its map's frame: every robot's path (its sessions in
// the map of its current one; a colour per robot of a fleet), and each
// candidate whose keyframes are in one map as a line, green if accepted, red
// if rejected, yellow if pending. An empty list of a map is sent as DELETE,
// which clears an old one.
template <class Pose>
visualization_msgs::MarkerArray GraphMarkers(rrr::Session<Pose>& session,
                                             const MapFrames& frames);

// The accepted graph of map `map` in `frame`: its keyframes at their
// corrected poses (ids as Session::Graph lays them out, each with its
// keyframe id and, for a fleet, its robot), their odometry and the accepted
// loops between them.
template <class Pose>
rrr_slam::AcceptedGraph AcceptedGraphMsg(rrr::Session<Pose>& session, int map,
                                         const std::string& frame);

// Writes every chain of the session at its corrected poses, its odometry and
// the accepted loops (every loop if `with_candidates`, each candidate then
// also as a comment line "# DECISION <from> <to> <state>[ waiting]", its
// ends named "<robot>:<id>", or "<id>" for one robot) to `path`, and says in
// `*res` whether it was written, as ~save_graph answers.
template <class Pose>
void SaveGraphFile(rrr::Session<Pose>& session, const std::string& path,
                   bool with_candidates, rrr_slam::SaveGraph::Response* res);

}  // namespace rrr_ros

#endif  // RRR_ROS_GRAPH_MESSAGES_H_
