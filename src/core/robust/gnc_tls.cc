#include "rrr/robust/gnc_tls.h"

#include <algorithm>
#include <cmath>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/graph/chain_spans.h"
#include "rrr/io/g2o.h"
#include "rrr/robust/reweighted_solve.h"
#include "rrr/rrr/chi_square.h"
#include "rrr/solver/chordal_initialization.h"

namespace rrr {

template <class Pose>
Verdict VerifyWithGncTls(const PoseGraph<Pose>& graph,
                         const GncTlsOptions& options, std::vector<Pose>* map,
                         MinimizeResult* minimized) {
  const double c2 = ChiSquareQuantile(options.inlier_probability)(Pose::kDof);
  double mu = -1.0;  // set from the first residuals
  const Reweigh reweigh = [&](const std::vector<double>& chi2,
                              std::vector<double>* weights) {
    if (mu < 0.0) {
      const double largest =
          chi2.empty() ? 0.0 : *std::max_element(chi2.begin(), chi2.end());
      if (largest <= c2) return true;  // every loop already an inlier
      mu = c2 / (2.0 * largest - c2);
    }
    bool binary = true;
    for (size_t k = 0; k < chi2.size(); ++k) {
      const double r2 = chi2[k];
      double& w = (*weights)[k];
      if (r2 >= (mu + 1.0) / mu * c2) {
        w = 0.0;
      } else if (r2 <= mu / (mu + 1.0) * c2) {
        w = 1.0;
      } else {
        w = std::sqrt(c2 * mu * (mu + 1.0) / r2) - mu;
        binary = false;
      }
    }
    mu *= options.mu_factor;
    return binary && mu > 1e4;
  };
  // Several chains start from the chordal start (each chain placed by every
  // loop), as nothing else relates their frames; one chain from odometry.
  std::vector<Pose> start;
  if (ChainSpansOf(graph).size() > 1) {
    start = ChordalInitialization(graph, AllLoops(graph));
  }
  const ReweightedResult<Pose> result = ReweightedSolve(
      graph, reweigh, ConvergenceOptions{options.max_iterations, 1e-9}, start);
  std::vector<bool> accepted(graph.loops().size());
  for (size_t k = 0; k < accepted.size(); ++k) {
    accepted[k] = result.weights[k] > 0.5;
  }
  if (map) *map = result.estimate;
  if (minimized) *minimized = result.minimize;
  return VerdictOf(accepted);
}

template Verdict VerifyWithGncTls(const PoseGraph<Pose2>&, const GncTlsOptions&,
                                  std::vector<Pose2>*, MinimizeResult*);
template Verdict VerifyWithGncTls(const PoseGraph<Pose3>&, const GncTlsOptions&,
                                  std::vector<Pose3>*, MinimizeResult*);

}  // namespace rrr
