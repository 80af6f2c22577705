#include "rrr/graph/pose_graph.h"

#include <algorithm>
#include <stdexcept>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/graph/disjoint_sets.h"

namespace rrr {

template <class Pose>
int PoseGraph<Pose>::AddPose(PoseId id, const Pose& estimate) {
  if (index_of_.count(id) > 0) {
    throw std::invalid_argument("pose id " + std::to_string(id) +
                                " is a pose already");
  }
  const int index = num_poses();
  ids_.push_back(id);
  index_of_.emplace(id, index);
  estimates_.push_back(estimate);
  return index;
}

template <class Pose>
void PoseGraph<Pose>::Reserve(int poses, int edges) {
  const int odometry = std::min(std::max(poses - 1, 0), edges);
  ids_.reserve(poses);
  index_of_.reserve(poses);
  estimates_.reserve(poses);
  odometry_.reserve(odometry);
  loops_.reserve(edges - odometry);
}

template <class Pose>
int PoseGraph<Pose>::IndexOf(PoseId id) const {
  const auto it = index_of_.find(id);
  return it == index_of_.end() ? -1 : it->second;
}

template <class Pose>
bool PoseGraph<Pose>::IsOdometry(int from, int to) const {
  const PoseId d = ids_.at(to) - ids_.at(from);
  return d == 1 || d == -1;
}

template <class Pose>
void PoseGraph<Pose>::AddEdge(const Edge& edge) {
  if (IsOdometry(edge.from, edge.to)) {
    odometry_.push_back(edge);
  } else {
    loops_.push_back(edge);
  }
}

template <class Pose>
std::vector<Pose> PoseGraph<Pose>::ComposeOdometry() const {
  // step[k]: the odometry measurement from pose k-1 to pose k, if any.
  std::vector<const Edge*> forward(num_poses(), nullptr);
  std::vector<const Edge*> backward(num_poses(), nullptr);
  for (const Edge& e : odometry_) {
    if (e.to == e.from + 1 && !forward[e.to]) forward[e.to] = &e;
    if (e.from == e.to + 1 && !backward[e.from]) backward[e.from] = &e;
  }
  std::vector<Pose> out = estimates_;
  for (int k = 1; k < num_poses(); ++k) {
    if (forward[k]) {
      out[k] = out[k - 1] * forward[k]->measurement;
    } else if (backward[k]) {
      out[k] = out[k - 1] * backward[k]->measurement.inverse();
    }
  }
  return out;
}

template <class Pose>
std::string PoseGraph<Pose>::CheckChain() const {
  std::vector<bool> linked(num_poses(), false);
  for (const Edge& e : odometry_) linked[std::max(e.from, e.to)] = true;
  for (int k = 1; k < num_poses(); ++k) {
    if (!linked[k]) {
      return "pose " + std::to_string(ids_[k]) +
             " has no odometry edge to pose " + std::to_string(ids_[k - 1]) +
             ": RRR needs one connected odometry chain";
    }
  }
  return "";
}

template <class Pose>
std::string PoseGraph<Pose>::CheckConnected(
    const std::vector<int>& loops) const {
  DisjointSets sets(num_poses());
  for (const Edge& e : odometry_) sets.Join(e.from, e.to);
  for (const int k : loops) sets.Join(loops_[k].from, loops_[k].to);
  for (int p = 1; p < num_poses(); ++p) {
    if (sets.Find(p) != 0) {
      return "pose " + std::to_string(ids_[p]) +
             " is not reached from the first pose by any edge: the graph is "
             "several maps";
    }
  }
  return "";
}

template class PoseGraph<Pose2>;
template class PoseGraph<Pose3>;

}  // namespace rrr
