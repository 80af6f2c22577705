// RRR's intra-cluster and inter-cluster consistency tests.
#ifndef RRR_RRR_CONSISTENCY_TESTS_H_
#define RRR_RRR_CONSISTENCY_TESTS_H_

#include <vector>

#include "rrr/rrr/chi_square.h"
#include "rrr/solver/consistency_solver.h"

namespace rrr {

// The gate of a solve's total error: D²_G < χ²(α, e·n), with n the number
// of active edges n_G or, with `span_gate`, the spanned edges n_S.
bool TotalErrorConsistent(const SubsetErrors& errors, int residual_dim,
                          const ChiSquareQuantile& chi2, bool span_gate);

// The intra-cluster decision on the errors of solving odometry plus
// `cluster`: if the total error passes its gate, the member loops with
// d²_l < χ²(α, e), in their given order; otherwise none.
std::vector<int> IntraClusterSurvivors(const std::vector<int>& cluster,
                                       const SubsetErrors& errors,
                                       int residual_dim,
                                       const ChiSquareQuantile& chi2,
                                       bool span_gate);

// Intra-cluster consistency (RRR_ALGORITHM.md §2). Solves odometry plus
// `cluster`; if the total error passes its gate, returns the member loops
// with d²_l < χ²(α, e), in their given order. Returns an empty list when the
// cluster is rejected.
std::vector<int> IntraClusterConsistent(const std::vector<int>& cluster,
                                        ConsistencySolver& solver,
                                        const ChiSquareQuantile& chi2,
                                        bool span_gate = false);

// Inter-cluster consistency (RRR_ALGORITHM.md §3) over clusters that passed
// the intra-cluster test, each given by its loops. Returns, for each cluster,
// whether it is in the accepted set `good` at the end.
std::vector<bool> InterClusterConsistent(
    const std::vector<std::vector<int>>& clusters, ConsistencySolver& solver,
    const ChiSquareQuantile& chi2, bool span_gate = false);

}  // namespace rrr

#endif  // RRR_RRR_CONSISTENCY_TESTS_H_
