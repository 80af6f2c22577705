// Rule 5 of VerifyChains (include/rrr/rrr/chains/verify_chains.h): the
// clusters inside chains judged again against the maps that joined them.
#ifndef RRR_CORE_RRR_CHAINS_JOINED_MAP_REVIEW_H_
#define RRR_CORE_RRR_CHAINS_JOINED_MAP_REVIEW_H_

#include <vector>

#include "rrr/graph/pose_graph.h"
#include "rrr/rrr/chains/verify_chains.h"
#include "rrr/rrr/decision_reason.h"
#include "rrr/rrr/options.h"

namespace rrr {

// Loops of one chain's cluster that a joined map refuted, and why.
struct RefutedGroup {
  int chain = 0;
  std::vector<int> loops;  // indices of the graph's, ascending
  DecisionReason reason;   // test kJoinedMap or kOutweighed
};

// Over each map of `judged` that joins several chains (its estimates that
// map's minimum with its accepted loops): the accepted clusters inside its
// chains (their loops as `judged` accepted them, grouped by cluster) are
// weighed by Δ, to first order how much higher the map's minimum is with a
// cluster's links than without them (PoseGraphSolver::ChangesOfMinimum),
// against the gate of the cluster's chain alone: its group scale for
// several links, its map scale for one, times χ²(α, e·n). While one is over
// its gate, the one most over it (Δ / gate) is taken out and the map
// minimized again; while none is, one of those taken out (`refuted` given,
// or taken out now) whose Δ back in is under its gate, the least over it
// first, is put back (once each). While neither, a cluster that its
// coalition outweighs is taken out and not put back: the clusters between
// chains of the map that rule 3 refused (tests kMap, kMapBound) and that
// would fit without it (to first order, PoseGraphSolver::ChangesOfMinimum's
// `without`), if two of them are separate evidence, weighed against it as
// RRR's reversal weighs two clusters (test kOutweighed); the one it
// outweighs most first. Returns the groups left out; those of
// `refuted` whose chain is in no joined map now are not among them. With
// `chains` given (ascending), only the clusters of those chains are weighed
// (and put back), in the maps that hold them, and only groups of them are
// returned.
template <class Pose>
std::vector<RefutedGroup> ReviewJoinedMaps(
    const PoseGraph<Pose>& graph, const ChainsVerdict<Pose>& judged,
    const std::vector<ChainAlone<Pose>>& alone,
    const std::vector<RefutedGroup>& refuted, const RrrOptions& options,
    const std::vector<int>& chains = {});

}  // namespace rrr

#endif  // RRR_CORE_RRR_CHAINS_JOINED_MAP_REVIEW_H_
