// RRR in batch: every loop candidate of a graph judged at once.
#ifndef RRR_RRR_PUBLISHED_BATCH_VERIFIER_H_
#define RRR_RRR_PUBLISHED_BATCH_VERIFIER_H_

#include <functional>
#include <vector>

#include "rrr/graph/pose_graph.h"
#include "rrr/rrr/options.h"
#include "rrr/rrr/verdict.h"
#include "rrr/solver/consistency_solver.h"

namespace rrr {

// Called with (clusters judged, clusters in all) as the intra-cluster tests
// progress.
using ProgressCallback = std::function<void(int done, int total)>;

// Runs RRR (RRR_ALGORITHM.md §1–3) on the loops whose end ids are
// `loop_ends[k]` (loop k of the solver), clustering them in ascending order
// of (a, b). Throws std::invalid_argument if `options` do not validate.
Verdict VerifyBatch(const std::vector<std::pair<PoseId, PoseId>>& loop_ends,
                    ConsistencySolver& solver, const RrrOptions& options,
                    const ProgressCallback& progress = nullptr);

}  // namespace rrr

#endif  // RRR_RRR_PUBLISHED_BATCH_VERIFIER_H_
