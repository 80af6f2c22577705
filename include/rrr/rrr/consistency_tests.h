// RRR's intra-cluster and inter-cluster consistency tests.
#ifndef RRR_RRR_CONSISTENCY_TESTS_H_
#define RRR_RRR_CONSISTENCY_TESTS_H_

#include <vector>

#include "rrr/rrr/chi_square.h"
#include "rrr/solver/consistency_solver.h"

namespace rrr {

// Intra-cluster consistency (RRR_ALGORITHM.md §2). Solves odometry plus
// `cluster`; if D²_G < χ²(α, e·n_G), returns the member loops with
// d²_l < χ²(α, e), in their given order. Returns an empty list when the
// cluster is rejected.
std::vector<int> IntraClusterConsistent(const std::vector<int>& cluster,
                                        ConsistencySolver& solver,
                                        const ChiSquareQuantile& chi2);

// Inter-cluster consistency (RRR_ALGORITHM.md §3) over clusters that passed
// the intra-cluster test, each given by its loops. Returns, for each cluster,
// whether it is in the accepted set `good` at the end.
std::vector<bool> InterClusterConsistent(
    const std::vector<std::vector<int>>& clusters, ConsistencySolver& solver,
    const ChiSquareQuantile& chi2);

}  // namespace rrr

#endif  // RRR_RRR_CONSISTENCY_TESTS_H_
