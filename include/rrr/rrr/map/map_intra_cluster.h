// Step 1 of the map procedure: which links of a cluster agree with the
// odometry and with each other.
#ifndef RRR_RRR_MAP_MAP_INTRA_CLUSTER_H_
#define RRR_RRR_MAP_MAP_INTRA_CLUSTER_H_

#include <vector>

#include "rrr/graph/odometry_chain.h"
#include "rrr/graph/pose_graph.h"
#include "rrr/rrr/chi_square.h"
#include "rrr/solver/convergence.h"

namespace rrr {

// What MapIntraCluster found.
struct IntraClusterOutcome {
  std::vector<int> survivors;  // the links kept; empty: the cluster fails
  // When some survive: the links the greedy left out that the odometry
  // does not refute alone. The odometry could not tell which links of the
  // cluster agree; a map that holds more may (MapVerifier, step 5).
  std::vector<int> left_out;
  bool refuted = false;   // some link was refuted by the odometry alone
  int solves = 0;         // condensed solves run
  int not_converged = 0;  // of them, stopped by the iteration limit
};

// The intra-cluster test of the map procedure (MapVerifier, step 1) on the
// loops `cluster` (graph.loops() indices), with gates s·χ²(α, dof):
//  - links whose D² minimized alone with the odometry, `alone_chi2`[loop]
//    (-1: that solve failed, which refutes nothing), is not under
//    s·χ²(α, e) are left out;
//  - the rest C is minimized with the odometry (SolveCondensed) while
//    D² ≥ s·χ²(α, e·|C|), dropping the link with the largest d²_l each
//    time; when D² passes, the links with d²_l < s·χ²(α, e) survive;
//  - if none survives, the links dropped before the drop that lowered D²
//    the most go through the same greedy alone, once.
// Survivors and left_out keep their order in `cluster`.
// `chain` must be the chain of `graph`.
template <class Pose>
IntraClusterOutcome MapIntraCluster(const PoseGraph<Pose>& graph,
                                    const OdometryChain<Pose>& chain,
                                    const std::vector<int>& cluster,
                                    const std::vector<double>& alone_chi2,
                                    double scale, const ChiSquareQuantile& chi2,
                                    const ConvergenceOptions& convergence);

}  // namespace rrr

#endif  // RRR_RRR_MAP_MAP_INTRA_CLUSTER_H_
