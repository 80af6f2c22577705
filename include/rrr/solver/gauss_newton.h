// Sparse Gauss–Newton over a pose graph with a subset of its loops active.
#ifndef RRR_SOLVER_GAUSS_NEWTON_H_
#define RRR_SOLVER_GAUSS_NEWTON_H_

#include <vector>

#include "rrr/graph/pose_graph.h"
#include "rrr/solver/consistency_solver.h"
#include "rrr/solver/local_problem.h"

namespace rrr {

// Gauss–Newton on the sparse normal equations (CHOLMOD), with the first pose
// (and any pose the graph marks fixed) held fixed.
//
// Each solve sets up only the problem its active loops make: the stretch of
// odometry chain between the first and the last pose they reach, plus those
// loops, with the first of them held fixed. The rest of the chain keeps its
// odometry shape and adds zero error (see Run), so the errors equal those of
// the whole graph. The sparsity pattern of that problem is ordered and
// analysed once per solve and refactorized numerically at each iteration.
//
// Solve() and Optimize() do not modify the solver and may run concurrently.
// The graph must outlive the solver and must not change while it exists.
template <class Pose>
class GaussNewton : public ConsistencySolver {
 public:
  // `iterations` is k, the number of iterations of each consistency Solve().
  GaussNewton(const PoseGraph<Pose>& graph, int iterations);

  SubsetErrors Solve(const std::vector<int>& active_loops) override;
  int residual_dim() const override { return Pose::kDof; }

  // Runs Gauss–Newton with odometry and `active_loops` until it converges,
  // from `start` (an estimate of every pose) if given, else from the
  // odometry initial estimate; returns the estimates of every pose and sets
  // `*iterations_run` if given.
  std::vector<Pose> Optimize(const std::vector<int>& active_loops,
                             const ConvergenceOptions& options,
                             int* iterations_run = nullptr,
                             const std::vector<Pose>* start = nullptr) const;

  // The odometry chain every solve starts from.
  const std::vector<Pose>& initial() const { return initial_; }
  // Errors of odometry and the given loops at estimates `x` (all poses).
  SubsetErrors Evaluate(const std::vector<int>& active_loops,
                        const std::vector<Pose>& x) const;

 private:
  // Runs up to `max_iterations` steps from `start` (default: the odometry
  // initial estimate); stops early when
  // `options` is given and the error stops decreasing. Sets `*spanned_edges`
  // (see SubsetErrors) if given. Returns false if the linear system could not
  // be solved.
  bool Run(const std::vector<int>& active_loops, int max_iterations,
           const ConvergenceOptions* options, std::vector<Pose>* x,
           int* iterations_run, int* spanned_edges = nullptr,
           const std::vector<Pose>* start = nullptr) const;

  const PoseGraph<Pose>& graph_;
  int iterations_;
  std::vector<Pose> initial_;
  int last_fixed_ = 0;  // the last pose held fixed
};

}  // namespace rrr

#endif  // RRR_SOLVER_GAUSS_NEWTON_H_
