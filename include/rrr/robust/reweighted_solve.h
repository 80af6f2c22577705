// Least squares over odometry and every loop with per-loop weights that are
// recomputed as the estimate changes: the machinery of robust kernels.
#ifndef RRR_ROBUST_REWEIGHTED_SOLVE_H_
#define RRR_ROBUST_REWEIGHTED_SOLVE_H_

#include <functional>
#include <vector>

#include "rrr/graph/pose_graph.h"
#include "rrr/solver/convergence.h"

namespace rrr {

// Sets the weights (in [0, 1], one per loop) from every loop's d²_l at the
// current estimate; returns true when they have settled (the solve then runs
// to convergence with them and stops).
using Reweigh = std::function<bool(const std::vector<double>& loop_chi2,
                                   std::vector<double>* weights)>;

// The result of ReweightedSolve.
template <class Pose>
struct ReweightedResult {
  std::vector<Pose> estimate;   // every pose
  std::vector<double> weights;  // of each loop at the end
  // Its iterations, whether it converged (the weights settled and the error
  // stopped decreasing) and the weighted error at the start and the end.
  MinimizeResult minimize;
};

// Starting from `start` (the odometry if empty) with every weight 1,
// alternates one Levenberg–Marquardt iteration on odometry plus the
// weighted loops (the first pose held; the damping carried over) with
// `reweigh`, until the weights settle and the error stops decreasing, or
// `options.max_iterations` iterations.
template <class Pose>
ReweightedResult<Pose> ReweightedSolve(const PoseGraph<Pose>& graph,
                                       const Reweigh& reweigh,
                                       const ConvergenceOptions& options,
                                       std::vector<Pose> start = {});

}  // namespace rrr

#endif  // RRR_ROBUST_REWEIGHTED_SOLVE_H_
