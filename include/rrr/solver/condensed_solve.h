// A consistency solve of a few loops against the odometry alone, on the
// poses the loops touch.
#ifndef RRR_SOLVER_CONDENSED_SOLVE_H_
#define RRR_SOLVER_CONDENSED_SOLVE_H_

#include <vector>

#include "rrr/graph/chain_odometry.h"
#include "rrr/graph/pose_graph.h"
#include "rrr/solver/consistency_solver.h"
#include "rrr/solver/local_problem.h"

namespace rrr {

// The result of SolveCondensed.
struct CondensedErrors {
  // total_chi2: the minimal error of the condensed odometry and the loops;
  // num_edges: the condensed odometry edges and the loops; loop_chi2: d²_l of
  // each loop in the order given.
  SubsetErrors errors;
  MinimizeResult minimize;
  // The chains the loops touch but the first: each one's frame was free,
  // so the minimum absorbs e of the loops' degrees of freedom per chain.
  int free_frames = 0;
};

// Minimizes the error of odometry plus `loops` (indices into graph.loops())
// over the poses the loops touch, from the odometry initial estimate, with
// the first of them held fixed. The odometry between consecutive touched
// poses of a chain is one edge (ChainOdometry::Between), so the cost does
// not depend on how far apart the loops' ends are. Loops between chains
// relate the chains' frames, which are otherwise free (each placed first by
// a loop that reaches it from a placed one); the loops must join every
// chain they touch. For a linear-Gaussian graph the minimal error equals
// that of the whole chains with the loops; its expected value is
// e·(|loops| − free_frames). `chains` must be the chains of `graph`. Poses
// the graph holds fixed (other than the first) are not supported: throws
// std::invalid_argument.
template <class Pose>
CondensedErrors SolveCondensed(const PoseGraph<Pose>& graph,
                               const ChainOdometry<Pose>& chains,
                               const std::vector<int>& loops,
                               const ConvergenceOptions& options);

}  // namespace rrr

#endif  // RRR_SOLVER_CONDENSED_SOLVE_H_
