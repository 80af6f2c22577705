#include "rrr/graph/chain_spans.h"

#include <algorithm>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"

namespace rrr {

template <class Pose>
std::vector<ChainSpan> ChainSpansOf(const PoseGraph<Pose>& graph) {
  std::vector<bool> linked(graph.num_poses(), false);
  for (const auto& e : graph.odometry()) linked[std::max(e.from, e.to)] = true;
  std::vector<ChainSpan> spans;
  for (int k = 0; k < graph.num_poses(); ++k) {
    if (k == 0 || !linked[k]) spans.push_back({k, k});
    spans.back().last = k;
  }
  return spans;
}

int ChainHolding(const std::vector<ChainSpan>& spans, int pose) {
  const auto it = std::upper_bound(
      spans.begin(), spans.end(), pose,
      [](int p, const ChainSpan& span) { return p < span.first; });
  return static_cast<int>(it - spans.begin()) - 1;
}

std::vector<int> Poses(const std::vector<ChainSpan>& spans) {
  std::vector<int> poses;
  for (const ChainSpan& span : spans) {
    for (int p = span.first; p <= span.last; ++p) poses.push_back(p);
  }
  return poses;
}

template <class Pose>
PoseGraph<Pose> SubGraph(const PoseGraph<Pose>& graph,
                         const std::vector<ChainSpan>& spans,
                         const std::vector<Pose>& estimates,
                         const std::vector<int>& loops) {
  PoseGraph<Pose> sub;
  std::vector<int> index(graph.num_poses(), -1);
  for (const int p : Poses(spans)) {
    index[p] = sub.AddPose(graph.ids()[p], estimates[p]);
  }
  const auto add = [&](Constraint<Pose> e) {
    e.from = index[e.from];
    e.to = index[e.to];
    sub.AddEdge(e);
  };
  for (const auto& e : graph.odometry()) {
    if (index[e.from] >= 0 && index[e.to] >= 0) add(e);
  }
  for (const int k : loops) add(graph.loops()[k]);
  return sub;
}

template <class Pose>
std::vector<OdometryChain<Pose>> OdometryOf(
    const PoseGraph<Pose>& graph, const std::vector<ChainSpan>& spans) {
  std::vector<OdometryChain<Pose>> chains;
  chains.reserve(spans.size());
  for (const ChainSpan& span : spans) {
    chains.push_back(ChainOf(SubGraph(graph, {span}, graph.estimates(), {})));
  }
  return chains;
}

template std::vector<OdometryChain<Pose2>> OdometryOf(
    const PoseGraph<Pose2>&, const std::vector<ChainSpan>&);
template std::vector<OdometryChain<Pose3>> OdometryOf(
    const PoseGraph<Pose3>&, const std::vector<ChainSpan>&);
template std::vector<ChainSpan> ChainSpansOf(const PoseGraph<Pose2>&);
template std::vector<ChainSpan> ChainSpansOf(const PoseGraph<Pose3>&);
template PoseGraph<Pose2> SubGraph(const PoseGraph<Pose2>&,
                                   const std::vector<ChainSpan>&,
                                   const std::vector<Pose2>&,
                                   const std::vector<int>&);
template PoseGraph<Pose3> SubGraph(const PoseGraph<Pose3>&,
                                   const std::vector<ChainSpan>&,
                                   const std::vector<Pose3>&,
                                   const std::vector<int>&);

}  // namespace rrr
