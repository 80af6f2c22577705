// The odometry chains of a pose graph: a robot's session each, its poses
// joined by odometry, the chains joined to each other only by loops.
#ifndef RRR_GRAPH_CHAIN_SPANS_H_
#define RRR_GRAPH_CHAIN_SPANS_H_

#include <vector>

#include "rrr/graph/odometry_chain.h"
#include "rrr/graph/pose_graph.h"

namespace rrr {

// The poses first..last (indices) of one odometry chain.
struct ChainSpan {
  int first = 0;
  int last = 0;
  int size() const { return last - first + 1; }
  bool Holds(int pose) const { return first <= pose && pose <= last; }
};

// The chains of `graph` in pose order: a new chain starts at every pose
// without odometry to its predecessor (PoseGraph::CheckChain's gaps). A graph
// with poses has at least one.
template <class Pose>
std::vector<ChainSpan> ChainSpansOf(const PoseGraph<Pose>& graph);

// The index of the chain of `spans` that holds `pose`.
int ChainHolding(const std::vector<ChainSpan>& spans, int pose);

// The graph of the chains `spans` (ascending, of `graph`; a span may be part
// of a chain): their poses with
// the estimates `estimates` (of every pose of `graph`), their odometry, and
// the loops `loops` (indices into graph.loops(), every end in those chains)
// in that order, so that loop k of the result is graph.loops()[loops[k]].
// Pose k of the result is pose Poses(spans)[k] of `graph`.
template <class Pose>
PoseGraph<Pose> SubGraph(const PoseGraph<Pose>& graph,
                         const std::vector<ChainSpan>& spans,
                         const std::vector<Pose>& estimates,
                         const std::vector<int>& loops);

// The poses of `spans`, in order.
std::vector<int> Poses(const std::vector<ChainSpan>& spans);

// The odometry of each of `spans` (chains of `graph`) condensed (ChainOf),
// its poses counted from the span's first.
template <class Pose>
std::vector<OdometryChain<Pose>> OdometryOf(
    const PoseGraph<Pose>& graph, const std::vector<ChainSpan>& spans);

}  // namespace rrr

#endif  // RRR_GRAPH_CHAIN_SPANS_H_
