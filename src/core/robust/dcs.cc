#include "rrr/robust/dcs.h"

#include <algorithm>
#include <cmath>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/robust/reweighted_solve.h"

namespace rrr {

template <class Pose>
Verdict VerifyWithDcs(const PoseGraph<Pose>& graph, const DcsOptions& options,
                      std::vector<Pose>* map, MinimizeResult* minimized) {
  const auto scale = [&](double chi2) {
    return std::min(1.0, 2.0 * options.phi / (options.phi + chi2));
  };
  std::vector<double> previous;
  const Reweigh reweigh = [&](const std::vector<double>& chi2,
                              std::vector<double>* weights) {
    for (size_t k = 0; k < chi2.size(); ++k) {
      (*weights)[k] = std::pow(scale(chi2[k]), 2);
    }
    const bool settled =
        !previous.empty() &&
        std::equal(weights->begin(), weights->end(), previous.begin(),
                   [](double a, double b) { return std::abs(a - b) < 1e-6; });
    previous = *weights;
    return settled;
  };
  const ReweightedResult<Pose> result = ReweightedSolve(
      graph, reweigh, ConvergenceOptions{options.max_iterations, 1e-9});
  std::vector<bool> accepted(graph.loops().size());
  for (size_t k = 0; k < accepted.size(); ++k) {
    accepted[k] = std::sqrt(result.weights[k]) > 0.5;
  }
  if (map) *map = result.estimate;
  if (minimized) *minimized = result.minimize;
  return VerdictOf(accepted);
}

template Verdict VerifyWithDcs(const PoseGraph<Pose2>&, const DcsOptions&,
                               std::vector<Pose2>*, MinimizeResult*);
template Verdict VerifyWithDcs(const PoseGraph<Pose3>&, const DcsOptions&,
                               std::vector<Pose3>*, MinimizeResult*);

}  // namespace rrr
