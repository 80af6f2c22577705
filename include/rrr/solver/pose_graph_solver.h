// The sparse least-squares solver of a pose graph with a subset of its loops
// active: RRR's fixed-iteration consistency solves and minimization to
// convergence.
#ifndef RRR_SOLVER_POSE_GRAPH_SOLVER_H_
#define RRR_SOLVER_POSE_GRAPH_SOLVER_H_

#include <memory>
#include <vector>

#include "rrr/graph/pose_graph.h"
#include "rrr/solver/consistency_solver.h"
#include "rrr/solver/convergence.h"

namespace rrr {

template <class Pose>
class LocalProblem;

// Least squares on the sparse normal equations (CHOLMOD), with the first pose
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
class PoseGraphSolver : public ConsistencySolver {
 public:
  // `iterations` is k, the number of iterations of each consistency Solve(),
  // taken as `steps` says.
  PoseGraphSolver(const PoseGraph<Pose>& graph, int iterations,
                  SolveSteps steps = SolveSteps::kGaussNewton);

  SubsetErrors Solve(const std::vector<int>& active_loops) override;
  int residual_dim() const override { return Pose::kDof; }

  // Minimizes the error of odometry and `active_loops` with
  // Levenberg–Marquardt (LocalProblem::Minimize) from `start` (an estimate of
  // every pose) if given, else from the odometry initial estimate; returns
  // the estimates of every pose and, in `*result` if given, whether it
  // converged within `options`, its iterations and its initial and final
  // error (of the whole graph's odometry and `active_loops`).
  std::vector<Pose> Optimize(const std::vector<int>& active_loops,
                             const ConvergenceOptions& options,
                             MinimizeResult* result = nullptr,
                             const std::vector<Pose>* start = nullptr) const;

  // At `x`, a minimum of odometry and `active_loops` (every pose): for each
  // group of loops (indices into graph.loops(), all active or all not), to
  // first order how much higher that minimum is with the group than
  // without it (LocalProblem::ChangesOfMinimum); `without` and `reach` as
  // there. Returns false if the problem's Gauss–Newton matrix is not
  // positive definite.
  bool ChangesOfMinimum(const std::vector<int>& active_loops,
                        const std::vector<std::vector<int>>& groups,
                        const std::vector<Pose>& x,
                        std::vector<double>* changes,
                        std::vector<std::vector<double>>* without = nullptr,
                        const std::vector<double>& reach = {}) const;

  // The odometry chain every solve starts from.
  const std::vector<Pose>& initial() const { return initial_; }
  // Errors of odometry and the given loops at estimates `x` (all poses).
  SubsetErrors Evaluate(const std::vector<int>& active_loops,
                        const std::vector<Pose>& x) const;

 private:
  // From `start` (default: the odometry initial estimate): with `options`,
  // minimizes (Levenberg–Marquardt) within them and sets `*minimized`; else
  // takes k iterations as `steps_` says. Sets `*spanned_edges` (see
  // SubsetErrors) if given. Returns false if the linear system could not be
  // solved.
  bool Run(const std::vector<int>& active_loops,
           const ConvergenceOptions* options, std::vector<Pose>* x,
           MinimizeResult* minimized, int* spanned_edges = nullptr,
           const std::vector<Pose>* start = nullptr) const;

  // The problem of odometry and `loops` over the stretch of chain they span
  // (its last pose in `*last`), or null if they span none; the last `probes`
  // of `loops` are its probes (LocalProblem).
  std::unique_ptr<LocalProblem<Pose>> Problem(const std::vector<int>& loops,
                                              int* last,
                                              size_t probes = 0) const;

  const PoseGraph<Pose>& graph_;
  int iterations_;
  SolveSteps steps_;
  std::vector<Pose> initial_;
  int last_fixed_ = 0;  // the last pose held fixed
};

}  // namespace rrr

#endif  // RRR_SOLVER_POSE_GRAPH_SOLVER_H_
