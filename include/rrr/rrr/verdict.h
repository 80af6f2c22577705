// What a verifier decided about a graph's loop candidates.
#ifndef RRR_RRR_VERDICT_H_
#define RRR_RRR_VERDICT_H_

#include <utility>
#include <vector>

#include "rrr/graph/pose_graph.h"
#include "rrr/rrr/clustering.h"
#include "rrr/rrr/decision_reason.h"

namespace rrr {

// The decisions of RRR over a set of loop candidates.
struct Verdict {
  std::vector<int> accepted;         // loop indices, ascending
  std::vector<int> rejected;         // loop indices, ascending
  std::vector<int> cluster_of_loop;  // cluster index of each loop
  std::vector<Cluster> clusters;
  // Why each loop is in its state; empty where the method records none.
  std::vector<DecisionReason> reasons;
};

// The verdict of per-loop decisions (accepted[k] for loop k), for methods
// without clusters.
Verdict VerdictOf(const std::vector<bool>& accepted);

// The loop end ids of a graph's candidates, as VerifyBatch takes them.
template <class Pose>
std::vector<std::pair<PoseId, PoseId>> LoopEnds(const PoseGraph<Pose>& graph) {
  std::vector<std::pair<PoseId, PoseId>> ends;
  for (const auto& loop : graph.loops()) {
    ends.emplace_back(graph.ids()[loop.from], graph.ids()[loop.to]);
  }
  return ends;
}

}  // namespace rrr

#endif  // RRR_RRR_VERDICT_H_
