#include "rrr/rrr/map/map_intra_cluster.h"

#include <algorithm>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/solver/condensed_solve.h"

namespace rrr {
namespace {

// The greedy drop on `links`: the survivors, empty if none; sets
// `*left_after_largest_fall` (if given) to the links left after the drop
// that lowered D² the most.
template <class Pose>
std::vector<int> GreedySurvivors(const PoseGraph<Pose>& graph,
                                 const OdometryChain<Pose>& chain,
                                 std::vector<int> links, double scale,
                                 const ChiSquareQuantile& chi2,
                                 const ConvergenceOptions& convergence,
                                 std::vector<int>* left_after_largest_fall,
                                 IntraClusterOutcome* outcome) {
  const int e = Pose::kDof;
  double previous_total = 0.0, largest_fall = 0.0;
  while (!links.empty()) {
    ++outcome->solves;
    const CondensedErrors intra =
        SolveCondensed(graph, chain, links, convergence);
    if (!intra.minimize.converged) ++outcome->not_converged;
    if (!intra.errors.solved) break;
    const std::vector<double>& d2 = intra.errors.loop_chi2;
    const double total = intra.errors.total_chi2;
    if (left_after_largest_fall && previous_total - total > largest_fall) {
      largest_fall = previous_total - total;
      *left_after_largest_fall = links;
    }
    previous_total = total;
    if (total < scale * chi2(e * static_cast<int>(links.size()))) {
      const double one_link = scale * chi2(e);
      std::vector<int> survivors;
      for (size_t k = 0; k < links.size(); ++k) {
        if (d2[k] < one_link) survivors.push_back(links[k]);
      }
      return survivors;
    }
    links.erase(links.begin() +
                (std::max_element(d2.begin(), d2.end()) - d2.begin()));
  }
  return {};
}

}  // namespace

template <class Pose>
IntraClusterOutcome MapIntraCluster(const PoseGraph<Pose>& graph,
                                    const OdometryChain<Pose>& chain,
                                    const std::vector<int>& cluster,
                                    const std::vector<double>& alone_chi2,
                                    double scale, const ChiSquareQuantile& chi2,
                                    const ConvergenceOptions& convergence) {
  IntraClusterOutcome outcome;
  // A link that the odometry refutes on its own cannot join a true group.
  const double one_link = scale * chi2(Pose::kDof);
  std::vector<int> members;
  for (const int loop : cluster) {
    if (alone_chi2[loop] < one_link) members.push_back(loop);
  }
  outcome.refuted = members.size() < cluster.size();
  std::vector<int> left;  // the links left after the largest fall of D²
  outcome.survivors = GreedySurvivors(graph, chain, members, scale, chi2,
                                      convergence, &left, &outcome);
  if (outcome.survivors.empty() && !left.empty() &&
      left.size() < members.size()) {
    // A revisit that a false group joined may have gone first: the links
    // dropped before D² fell most, alone.
    std::vector<int> dropped_first;
    for (const int loop : members) {
      if (std::find(left.begin(), left.end(), loop) == left.end()) {
        dropped_first.push_back(loop);
      }
    }
    outcome.survivors = GreedySurvivors(graph, chain, dropped_first, scale,
                                        chi2, convergence, nullptr, &outcome);
  }
  if (!outcome.survivors.empty()) {
    for (const int loop : members) {
      if (std::find(outcome.survivors.begin(), outcome.survivors.end(), loop) ==
          outcome.survivors.end()) {
        outcome.left_out.push_back(loop);
      }
    }
  }
  return outcome;
}

template IntraClusterOutcome MapIntraCluster(const PoseGraph<Pose2>&,
                                             const OdometryChain<Pose2>&,
                                             const std::vector<int>&,
                                             const std::vector<double>&, double,
                                             const ChiSquareQuantile&,
                                             const ConvergenceOptions&);
template IntraClusterOutcome MapIntraCluster(const PoseGraph<Pose3>&,
                                             const OdometryChain<Pose3>&,
                                             const std::vector<int>&,
                                             const std::vector<double>&, double,
                                             const ChiSquareQuantile&,
                                             const ConvergenceOptions&);

}  // namespace rrr
