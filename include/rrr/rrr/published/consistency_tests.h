// RRR's intra-cluster and inter-cluster consistency tests.
#ifndef RRR_RRR_PUBLISHED_CONSISTENCY_TESTS_H_
#define RRR_RRR_PUBLISHED_CONSISTENCY_TESTS_H_

#include <vector>

#include "rrr/rrr/chi_square.h"
#include "rrr/solver/consistency_solver.h"

namespace rrr {

// The gate of a solve's total error: D²_G < χ²(α, e·n), with n the number
// of active edges n_G or, with `span_gate`, the spanned edges n_S.
bool TotalErrorConsistent(const SubsetErrors& errors, int residual_dim,
                          const ChiSquareQuantile& chi2, bool span_gate);

// Intra-cluster consistency (RRR_ALGORITHM.md §2), decided on the errors of
// solving odometry plus `cluster`: if the total error passes its gate, the
// member loops with d²_l < χ²(α, e), in their given order; otherwise none.
std::vector<int> IntraClusterSurvivors(const std::vector<int>& cluster,
                                       const SubsetErrors& errors,
                                       int residual_dim,
                                       const ChiSquareQuantile& chi2,
                                       bool span_gate);

// Inter-cluster consistency (RRR_ALGORITHM.md §3) over clusters that passed
// the intra-cluster test, each given by its loops. Returns, for each cluster,
// whether it is in the accepted set `good` at the end. Up to `threads`
// solves run at once (see RrrOptions::threads); the result does not depend
// on it.
std::vector<bool> InterClusterConsistent(
    const std::vector<std::vector<int>>& clusters, ConsistencySolver& solver,
    const ChiSquareQuantile& chi2, bool span_gate = false, int threads = 1);

}  // namespace rrr

#endif  // RRR_RRR_PUBLISHED_CONSISTENCY_TESTS_H_
