// RRR in batch: every loop candidate of a graph judged at once.
#ifndef RRR_RRR_BATCH_VERIFIER_H_
#define RRR_RRR_BATCH_VERIFIER_H_

#include <functional>
#include <vector>

#include "rrr/graph/pose_graph.h"
#include "rrr/rrr/clustering.h"
#include "rrr/rrr/options.h"
#include "rrr/solver/consistency_solver.h"

namespace rrr {

// The decisions of RRR over a set of loop candidates.
struct Verdict {
  std::vector<int> accepted;         // loop indices, ascending
  std::vector<int> rejected;         // loop indices, ascending
  std::vector<int> cluster_of_loop;  // cluster index of each loop
  std::vector<Cluster> clusters;
};

// The verdict of per-loop decisions (accepted[k] for loop k), for methods
// without clusters.
Verdict VerdictOf(const std::vector<bool>& accepted);

// Called with (clusters judged, clusters in all) as the intra-cluster tests
// progress.
using ProgressCallback = std::function<void(int done, int total)>;

// Runs RRR (RRR_ALGORITHM.md §1–3) on the loops whose end ids are
// `loop_ends[k]` (loop k of the solver), clustering them in ascending order
// of (a, b). Throws std::invalid_argument if `options` do not validate.
Verdict VerifyBatch(const std::vector<std::pair<PoseId, PoseId>>& loop_ends,
                    ConsistencySolver& solver, const RrrOptions& options,
                    const ProgressCallback& progress = nullptr);

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

#endif  // RRR_RRR_BATCH_VERIFIER_H_
