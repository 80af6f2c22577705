#include "rrr/rrr/published/batch_verifier.h"

#include <stdexcept>

#include "rrr/rrr/chi_square.h"
#include "rrr/rrr/published/consistency_tests.h"
#include "rrr/solver/solve_in_parallel.h"

namespace rrr {

Verdict VerifyBatch(const std::vector<std::pair<PoseId, PoseId>>& loop_ends,
                    ConsistencySolver& solver, const RrrOptions& options,
                    const ProgressCallback& progress) {
  const std::string problem = options.Validate();
  if (!problem.empty()) throw std::invalid_argument(problem);
  const ChiSquareQuantile chi2(options.alpha);

  Verdict verdict;
  verdict.clusters = ClusterInBatchOrder(loop_ends, options.cluster_window,
                                         &verdict.cluster_of_loop);

  const int num_clusters = static_cast<int>(verdict.clusters.size());
  std::vector<std::vector<int>> members;
  for (const Cluster& c : verdict.clusters) members.push_back(c.loops);
  int done = 0;
  const std::vector<SubsetErrors> errors =
      SolveInParallel(solver, members, options.threads, [&] {
        if (progress) progress(++done, num_clusters);
      });
  std::vector<std::vector<int>> survivors;
  for (int c = 0; c < num_clusters; ++c) {
    std::vector<int> kept = IntraClusterSurvivors(
        members[c], errors[c], solver.residual_dim(), chi2, options.span_gate);
    if (!kept.empty()) survivors.push_back(std::move(kept));
  }
  const std::vector<bool> good = InterClusterConsistent(
      survivors, solver, chi2, options.span_gate, options.threads);

  std::vector<bool> accepted(loop_ends.size(), false);
  for (size_t c = 0; c < survivors.size(); ++c) {
    if (!good[c]) continue;
    for (const int k : survivors[c]) accepted[k] = true;
  }
  for (size_t k = 0; k < loop_ends.size(); ++k) {
    (accepted[k] ? verdict.accepted : verdict.rejected)
        .push_back(static_cast<int>(k));
  }
  return verdict;
}

}  // namespace rrr
