#include "rrr/solver/pose_graph_solver.h"

#include <algorithm>
#include <limits>
#include <memory>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/solver/edge_error.h"
#include "rrr/solver/local_problem.h"

namespace rrr {

template <class Pose>
PoseGraphSolver<Pose>::PoseGraphSolver(const PoseGraph<Pose>& graph,
                                       int iterations, SolveSteps steps)
    : graph_(graph),
      iterations_(iterations),
      steps_(steps),
      initial_(graph.ComposeOdometry()) {
  for (const int k : graph.fixed()) last_fixed_ = std::max(last_fixed_, k);
}

template <class Pose>
std::unique_ptr<LocalProblem<Pose>> PoseGraphSolver<Pose>::Problem(
    const std::vector<int>& loops, int* last, size_t probes) const {
  // The stretch of chain that the loops (and fixed poses) span. The chain
  // after it hangs free and follows odometry with zero error. The chain
  // before it is a rigid path from the fixed first pose: relative-pose
  // errors do not change under a rigid motion of the rest, so every
  // Gauss–Newton step leaves that path at odometry with zero error, exactly
  // as if its last pose were fixed.
  int first = last_fixed_ > 0 ? 0 : graph_.num_poses() - 1;
  *last = last_fixed_;
  for (const int k : loops) {
    const auto& loop = graph_.loops()[k];
    first = std::min({first, loop.from, loop.to});
    *last = std::max({*last, loop.from, loop.to});
  }
  if (*last <= first) return nullptr;
  std::vector<int> free;
  std::vector<bool> fixed(*last - first + 1, false);
  fixed[0] = true;
  for (const int k : graph_.fixed()) {
    if (k >= first && k <= *last) fixed[k - first] = true;
  }
  for (int p = first; p <= *last; ++p) {
    if (!fixed[p - first]) free.push_back(p);
  }
  std::vector<const Constraint<Pose>*> edges;
  for (const auto& e : graph_.odometry()) {
    if (std::min(e.from, e.to) >= first && std::max(e.from, e.to) <= *last) {
      edges.push_back(&e);
    }
  }
  for (const int k : loops) edges.push_back(&graph_.loops()[k]);
  const size_t weighed = edges.size() - probes;
  return std::make_unique<LocalProblem<Pose>>(graph_.num_poses(), free,
                                              std::move(edges), weighed);
}

template <class Pose>
bool PoseGraphSolver<Pose>::Run(const std::vector<int>& active_loops,
                                const ConvergenceOptions* options,
                                std::vector<Pose>* x, MinimizeResult* minimized,
                                int* spanned_edges,
                                const std::vector<Pose>* start) const {
  *x = start ? *start : initial_;
  if (spanned_edges) *spanned_edges = 0;
  int last = 0;
  const std::unique_ptr<LocalProblem<Pose>> made = Problem(active_loops, &last);
  if (!made) {
    if (minimized) minimized->converged = true;
    return true;
  }
  LocalProblem<Pose>& problem = *made;
  if (spanned_edges) {
    *spanned_edges = static_cast<int>(problem.edges().size());
  }
  if (options) {
    *minimized = problem.Minimize(x, *options);
    if (!minimized->solved) return false;
  } else if (steps_ == SolveSteps::kGaussNewton) {
    for (int it = 0; it < iterations_; ++it) {
      if (!problem.Step(x)) return false;
    }
  } else {
    TrustRegion region;
    for (int it = 0; it < iterations_; ++it) {
      double before = 0.0, after = 0.0;
      const StepOutcome outcome =
          problem.StepWithin(&region, x, &before, &after);
      if (outcome == StepOutcome::kNotSolved) return false;
      if (outcome == StepOutcome::kNoDecrease) break;
    }
  }
  // The free end of the chain follows its last constrained pose.
  for (int p = last + 1; p < graph_.num_poses(); ++p) {
    (*x)[p] = (*x)[last] * initial_[last].between(initial_[p]);
  }
  return true;
}

template <class Pose>
bool PoseGraphSolver<Pose>::ChangesOfMinimum(
    const std::vector<int>& active_loops,
    const std::vector<std::vector<int>>& groups, const std::vector<Pose>& x,
    std::vector<double>* changes, std::vector<std::vector<double>>* without,
    const std::vector<double>& reach) const {
  std::vector<int> loops = active_loops;
  std::vector<int> edge_of_loop(graph_.loops().size(), -1);
  for (size_t k = 0; k < active_loops.size(); ++k) {
    edge_of_loop[active_loops[k]] = static_cast<int>(k);
  }
  for (const std::vector<int>& group : groups) {
    for (const int k : group) {
      if (edge_of_loop[k] >= 0) continue;
      edge_of_loop[k] = static_cast<int>(loops.size());
      loops.push_back(k);
    }
  }
  int last = 0;
  // The inactive loops are probes: they add no fill-in to the factor.
  const std::unique_ptr<LocalProblem<Pose>> problem =
      Problem(loops, &last, loops.size() - active_loops.size());
  if (!problem) return false;
  // The problem's edges: its odometry, then `loops`, the inactive at 0.
  const int odometry = static_cast<int>(problem->edges().size() - loops.size());
  std::vector<double> weights(problem->edges().size(), 1.0);
  std::fill(weights.begin() + odometry + active_loops.size(), weights.end(),
            0.0);
  problem->SetWeights(std::move(weights));
  std::vector<std::vector<int>> edge_groups;
  for (const std::vector<int>& group : groups) {
    edge_groups.emplace_back();
    for (const int k : group) {
      edge_groups.back().push_back(odometry + edge_of_loop[k]);
    }
  }
  return problem->ChangesOfMinimum(x, edge_groups, changes, without, reach);
}

template <class Pose>
SubsetErrors PoseGraphSolver<Pose>::Evaluate(
    const std::vector<int>& active_loops, const std::vector<Pose>& x) const {
  SubsetErrors out;
  for (const auto& e : graph_.odometry()) out.total_chi2 += EdgeChi2(e, x);
  out.loop_chi2.reserve(active_loops.size());
  for (const int k : active_loops) {
    out.loop_chi2.push_back(EdgeChi2(graph_.loops()[k], x));
    out.total_chi2 += out.loop_chi2.back();
  }
  out.num_edges =
      static_cast<int>(graph_.odometry().size() + active_loops.size());
  return out;
}

template <class Pose>
SubsetErrors PoseGraphSolver<Pose>::Solve(
    const std::vector<int>& active_loops) {
  std::vector<Pose> x;
  int spanned_edges = 0;
  if (!Run(active_loops, nullptr, &x, nullptr, &spanned_edges)) {
    SubsetErrors failed;
    failed.solved = false;
    failed.num_edges =
        static_cast<int>(graph_.odometry().size() + active_loops.size());
    failed.total_chi2 = std::numeric_limits<double>::infinity();
    failed.loop_chi2.assign(active_loops.size(), failed.total_chi2);
    failed.num_spanned_edges = spanned_edges;
    return failed;
  }
  SubsetErrors errors = Evaluate(active_loops, x);
  errors.num_spanned_edges = spanned_edges;
  return errors;
}

template <class Pose>
std::vector<Pose> PoseGraphSolver<Pose>::Optimize(
    const std::vector<int>& active_loops, const ConvergenceOptions& options,
    MinimizeResult* result, const std::vector<Pose>* start) const {
  std::vector<Pose> x;
  MinimizeResult minimized;
  Run(active_loops, &options, &x, &minimized, nullptr, start);
  if (result) {
    // The local problem's errors leave out the edges outside it; give the
    // whole graph's.
    *result = minimized;
    result->initial_chi2 =
        Evaluate(active_loops, start ? *start : initial_).total_chi2;
    result->final_chi2 = Evaluate(active_loops, x).total_chi2;
  }
  return x;
}

template class PoseGraphSolver<Pose2>;
template class PoseGraphSolver<Pose3>;

}  // namespace rrr
