// The problem: poses, odometry edges and loop-closure candidates.
#ifndef RRR_GRAPH_POSE_GRAPH_H_
#define RRR_GRAPH_POSE_GRAPH_H_

#include <Eigen/Core>
#include <algorithm>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

namespace rrr {

using PoseId = std::int64_t;

// A relative-pose measurement z between poses `from` and `to` (indices into
// the graph's poses): z ≈ x_from⁻¹ · x_to, with its information matrix.
template <class Pose>
struct Constraint {
  using Information = Eigen::Matrix<double, Pose::kDof, Pose::kDof>;
  int from = 0;
  int to = 0;
  Pose measurement;
  Information information = Information::Identity();
};

// A pose graph in the sense of RRR: poses x_0..x_n ordered by id, odometry
// edges between consecutive poses, and loop candidates between any other pair.
// Indices (0..n-1) address poses inside the library; ids are what the user
// and files use.
template <class Pose>
class PoseGraph {
 public:
  using Edge = Constraint<Pose>;

  // Appends a pose with the given id and initial estimate; returns its
  // index. Throws std::invalid_argument if `id` is a pose already. (A graph
  // read from a file has its ids in increasing order: the chain functions
  // below read its chains in index order.)
  int AddPose(PoseId id, const Pose& estimate);
  // Makes room for `poses` poses and `edges` edges in all, the odometry
  // between consecutive poses and the rest loops, so that adding them moves
  // nothing already added.
  void Reserve(int poses, int edges);
  // Returns the index of `id`, or -1 if there is no such pose.
  int IndexOf(PoseId id) const;

  // An edge is odometry when its poses' ids differ by exactly one, otherwise
  // it is a loop candidate. Both indices must already exist.
  void AddEdge(const Edge& edge);
  bool IsOdometry(int from, int to) const;

  // The poses are marked as held fixed by the solver (g2o's FIX). The first
  // pose is always held fixed as well.
  void Fix(int index) { fixed_.push_back(index); }

  int num_poses() const { return static_cast<int>(ids_.size()); }
  const std::vector<PoseId>& ids() const { return ids_; }
  const std::vector<Pose>& estimates() const { return estimates_; }
  std::vector<Pose>& mutable_estimates() { return estimates_; }
  const std::vector<Edge>& odometry() const { return odometry_; }
  const std::vector<Edge>& loops() const { return loops_; }
  const std::vector<int>& fixed() const { return fixed_; }

  // The odometry chain composed from the first pose's estimate: the initial
  // estimate of RRR. Poses without odometry to their predecessor keep their
  // estimate (see CheckChain).
  std::vector<Pose> ComposeOdometry() const;
  // Returns an empty string if every pose after the first is linked to its
  // predecessor by an odometry edge, otherwise a message naming the first gap.
  std::string CheckChain() const;
  // Returns an empty string if every pose is reached from the first by its
  // odometry and the loops `loops` (indices into loops()), otherwise a
  // message naming the first pose that is not: such a graph is several maps
  // whose relative pose nothing determines.
  std::string CheckConnected(const std::vector<int>& loops) const;

 private:
  std::vector<PoseId> ids_;
  std::unordered_map<PoseId, int> index_of_;
  std::vector<Pose> estimates_;
  std::vector<Edge> odometry_;
  std::vector<Edge> loops_;
  std::vector<int> fixed_;
};

// The poses (indices) that the graph's loops `loops` touch, ascending, each
// once.
template <class Pose>
std::vector<int> PosesTouched(const PoseGraph<Pose>& graph,
                              const std::vector<int>& loops) {
  std::vector<int> poses;
  poses.reserve(2 * loops.size());
  for (const int k : loops) {
    poses.push_back(graph.loops()[k].from);
    poses.push_back(graph.loops()[k].to);
  }
  std::sort(poses.begin(), poses.end());
  poses.erase(std::unique(poses.begin(), poses.end()), poses.end());
  return poses;
}

}  // namespace rrr

#endif  // RRR_GRAPH_POSE_GRAPH_H_
