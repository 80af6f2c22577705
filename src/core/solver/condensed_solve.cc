#include "rrr/solver/condensed_solve.h"

#include <algorithm>
#include <stdexcept>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/solver/edge_error.h"

namespace rrr {

template <class Pose>
CondensedErrors SolveCondensed(const PoseGraph<Pose>& graph,
                               const OdometryChain<Pose>& chain,
                               const std::vector<int>& loops,
                               const ConvergenceOptions& options) {
  for (const int k : graph.fixed()) {
    if (k != 0) {
      throw std::invalid_argument(
          "condensed solves hold only the first pose fixed");
    }
  }
  const std::vector<int> touched = PosesTouched(graph, loops);
  const auto local = [&](int pose) {
    return static_cast<int>(
        std::lower_bound(touched.begin(), touched.end(), pose) -
        touched.begin());
  };

  std::vector<Constraint<Pose>> edges;
  edges.reserve(touched.size() + loops.size());
  for (size_t k = 0; k + 1 < touched.size(); ++k) {
    Constraint<Pose> e = chain.Between(touched[k], touched[k + 1]);
    e.from = static_cast<int>(k);
    e.to = static_cast<int>(k + 1);
    edges.push_back(e);
  }
  for (const int k : loops) {
    Constraint<Pose> e = graph.loops()[k];
    e.from = local(e.from);
    e.to = local(e.to);
    edges.push_back(e);
  }
  std::vector<Pose> x(touched.size());
  for (size_t k = 1; k < touched.size(); ++k) {
    x[k] = x[k - 1] * edges[k - 1].measurement;
  }
  std::vector<int> free(touched.size() > 0 ? touched.size() - 1 : 0);
  for (size_t k = 0; k < free.size(); ++k) free[k] = static_cast<int>(k + 1);
  std::vector<const Constraint<Pose>*> pointers;
  pointers.reserve(edges.size());
  for (const auto& e : edges) pointers.push_back(&e);

  CondensedErrors out;
  LocalProblem<Pose> problem(static_cast<int>(x.size()), free, pointers);
  out.minimize = problem.Minimize(&x, options);
  out.errors.solved = out.minimize.solved;
  out.errors.num_edges = static_cast<int>(edges.size());
  out.errors.num_spanned_edges = out.errors.num_edges;
  out.errors.total_chi2 = out.minimize.final_chi2;
  for (size_t k = touched.size() > 0 ? touched.size() - 1 : 0; k < edges.size();
       ++k) {
    out.errors.loop_chi2.push_back(EdgeChi2(edges[k], x));
  }
  return out;
}

template CondensedErrors SolveCondensed(const PoseGraph<Pose2>&,
                                        const OdometryChain<Pose2>&,
                                        const std::vector<int>&,
                                        const ConvergenceOptions&);
template CondensedErrors SolveCondensed(const PoseGraph<Pose3>&,
                                        const OdometryChain<Pose3>&,
                                        const std::vector<int>&,
                                        const ConvergenceOptions&);

}  // namespace rrr
