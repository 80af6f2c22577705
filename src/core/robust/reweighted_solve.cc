#include "rrr/robust/reweighted_solve.h"

#include <utility>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/solver/edge_error.h"
#include "rrr/solver/local_problem.h"

namespace rrr {

template <class Pose>
ReweightedResult<Pose> ReweightedSolve(const PoseGraph<Pose>& graph,
                                       const Reweigh& reweigh,
                                       const ConvergenceOptions& options,
                                       std::vector<Pose> start) {
  ReweightedResult<Pose> result;
  result.estimate = start.empty() ? graph.ComposeOdometry() : std::move(start);
  const size_t odometry = graph.odometry().size();
  const size_t loops = graph.loops().size();
  std::vector<const Constraint<Pose>*> edges;
  for (const auto& e : graph.odometry()) edges.push_back(&e);
  for (const auto& e : graph.loops()) edges.push_back(&e);
  std::vector<int> free;
  for (int p = 1; p < graph.num_poses(); ++p) free.push_back(p);
  LocalProblem<Pose> problem(graph.num_poses(), free, edges);

  result.weights.assign(loops, 1.0);
  std::vector<double> weights(odometry + loops, 1.0);
  std::vector<double> loop_chi2(loops);
  TrustRegion region;
  region.relative_decrease = options.relative_decrease;
  bool settled = false;
  MinimizeResult& minimize = result.minimize;
  while (minimize.iterations < options.max_iterations) {
    for (size_t k = 0; k < loops; ++k) {
      loop_chi2[k] = EdgeChi2(graph.loops()[k], result.estimate);
    }
    if (!settled) settled = reweigh(loop_chi2, &result.weights);
    std::copy(result.weights.begin(), result.weights.end(),
              weights.begin() + static_cast<std::ptrdiff_t>(odometry));
    problem.SetWeights(weights);
    double before = 0.0, after = 0.0;
    const StepOutcome outcome =
        problem.StepWithin(&region, &result.estimate, &before, &after);
    if (minimize.iterations == 0) minimize.initial_chi2 = before;
    minimize.final_chi2 = after;
    if (outcome == StepOutcome::kNotSolved) {
      minimize.solved = false;
      break;
    }
    ++minimize.iterations;
    if (settled && (outcome == StepOutcome::kNoDecrease ||
                    before - after <= options.relative_decrease * after)) {
      minimize.converged = true;
      break;
    }
  }
  return result;
}

template ReweightedResult<Pose2> ReweightedSolve(const PoseGraph<Pose2>&,
                                                 const Reweigh&,
                                                 const ConvergenceOptions&,
                                                 std::vector<Pose2>);
template ReweightedResult<Pose3> ReweightedSolve(const PoseGraph<Pose3>&,
                                                 const Reweigh&,
                                                 const ConvergenceOptions&,
                                                 std::vector<Pose3>);

}  // namespace rrr
