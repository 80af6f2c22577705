// Whether two clusters of loops between the same two chains are separate
// evidence (VerifyChains, rules 2 and 5).
#ifndef RRR_CORE_RRR_CHAINS_SEPARATE_EVIDENCE_H_
#define RRR_CORE_RRR_CHAINS_SEPARATE_EVIDENCE_H_

#include <algorithm>
#include <array>
#include <limits>
#include <vector>

#include "rrr/graph/chain_spans.h"
#include "rrr/graph/pose_graph.h"

namespace rrr {

// Whether the loops `x` and `y` of `graph` (indices of graph.loops(), each
// between `second` and one other chain, the same for all) are more than
// `window` ids apart on at least one of the two chains: a revisit that the
// clustering split in two, or one false group, is one piece of evidence,
// however many clusters it makes.
template <class Pose>
bool SeparateEvidence(const PoseGraph<Pose>& graph, const ChainSpan& second,
                      const std::vector<int>& x, const std::vector<int>& y,
                      PoseId window) {
  // The least and largest id each set of loops touches on either chain.
  const auto ranges = [&](const std::vector<int>& loops) {
    std::array<PoseId, 4> r{
        std::numeric_limits<PoseId>::max(), std::numeric_limits<PoseId>::min(),
        std::numeric_limits<PoseId>::max(), std::numeric_limits<PoseId>::min()};
    for (const int k : loops) {
      const auto& e = graph.loops()[k];
      for (const int p : {e.from, e.to}) {
        const int side = second.Holds(p) ? 2 : 0;
        r[side] = std::min(r[side], graph.ids()[p]);
        r[side + 1] = std::max(r[side + 1], graph.ids()[p]);
      }
    }
    return r;
  };
  const std::array<PoseId, 4> a = ranges(x), b = ranges(y);
  for (const int side : {0, 2}) {
    const PoseId gap = std::max(b[side] - a[side + 1], a[side] - b[side + 1]);
    if (gap > window) return true;
  }
  return false;
}

}  // namespace rrr

#endif  // RRR_CORE_RRR_CHAINS_SEPARATE_EVIDENCE_H_
