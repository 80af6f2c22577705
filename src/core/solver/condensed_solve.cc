#include "rrr/solver/condensed_solve.h"

#include <algorithm>
#include <stdexcept>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/solver/edge_error.h"

namespace rrr {

template <class Pose>
CondensedErrors SolveCondensed(const PoseGraph<Pose>& graph,
                               const ChainOdometry<Pose>& chains,
                               const std::vector<int>& loops,
                               const ConvergenceOptions& options) {
  for (const int k : graph.fixed()) {
    if (k != 0) {
      throw std::invalid_argument(
          "condensed solves hold only the first pose fixed");
    }
  }
  // The touched poses chain by chain, each chain's in order.
  std::vector<int> touched = PosesTouched(graph, loops);
  std::sort(touched.begin(), touched.end(),
            [&](int p, int q) { return chains.Key(p) < chains.Key(q); });
  const auto local = [&](int pose) {
    return static_cast<int>(
        std::lower_bound(
            touched.begin(), touched.end(), pose,
            [&](int p, int q) { return chains.Key(p) < chains.Key(q); }) -
        touched.begin());
  };

  std::vector<Constraint<Pose>> edges;
  edges.reserve(touched.size() + loops.size());
  // Each touched pose's estimate from its chain's first touched pose.
  std::vector<Pose> x(touched.size());
  std::vector<int> first_of(touched.size(), 0);  // its chain's first touched
  for (size_t k = 1; k < touched.size(); ++k) {
    if (chains.chain_of(touched[k]) != chains.chain_of(touched[k - 1])) {
      first_of[k] = static_cast<int>(k);
      continue;
    }
    Constraint<Pose> e = chains.Between(touched[k - 1], touched[k]);
    e.from = static_cast<int>(k - 1);
    e.to = static_cast<int>(k);
    edges.push_back(e);
    x[k] = x[k - 1] * e.measurement;
    first_of[k] = first_of[k - 1];
  }
  const size_t num_odometry = edges.size();
  for (const int k : loops) {
    Constraint<Pose> e = graph.loops()[k];
    e.from = local(e.from);
    e.to = local(e.to);
    edges.push_back(e);
  }
  // Each other chain placed by a loop from a placed one.
  std::vector<bool> placed(touched.size(), false);
  for (size_t k = 0; k < touched.size() && first_of[k] == 0; ++k) {
    placed[k] = true;
  }
  CondensedErrors out;
  for (bool more = true; more;) {
    more = false;
    for (size_t k = num_odometry; k < edges.size(); ++k) {
      const Constraint<Pose>& e = edges[k];
      if (placed[e.from] == placed[e.to]) continue;
      const bool forward = placed[e.from];
      const int to = forward ? e.to : e.from;
      const Pose at = forward ? x[e.from] * e.measurement
                              : x[e.to] * e.measurement.inverse();
      const Pose frame = at * x[to].inverse();
      for (size_t m = 0; m < touched.size(); ++m) {
        if (first_of[m] != first_of[to]) continue;
        x[m] = frame * x[m];
        placed[m] = true;
      }
      ++out.free_frames;
      more = true;
    }
  }
  std::vector<int> free(touched.size() > 0 ? touched.size() - 1 : 0);
  for (size_t k = 0; k < free.size(); ++k) free[k] = static_cast<int>(k + 1);
  std::vector<const Constraint<Pose>*> pointers;
  pointers.reserve(edges.size());
  for (const auto& e : edges) pointers.push_back(&e);

  LocalProblem<Pose> problem(static_cast<int>(x.size()), free, pointers);
  out.minimize = problem.Minimize(&x, options);
  out.errors.solved = out.minimize.solved;
  out.errors.num_edges = static_cast<int>(edges.size());
  out.errors.num_spanned_edges = out.errors.num_edges;
  out.errors.total_chi2 = out.minimize.final_chi2;
  for (size_t k = num_odometry; k < edges.size(); ++k) {
    out.errors.loop_chi2.push_back(EdgeChi2(edges[k], x));
  }
  return out;
}

template CondensedErrors SolveCondensed(const PoseGraph<Pose2>&,
                                        const ChainOdometry<Pose2>&,
                                        const std::vector<int>&,
                                        const ConvergenceOptions&);
template CondensedErrors SolveCondensed(const PoseGraph<Pose3>&,
                                        const ChainOdometry<Pose3>&,
                                        const std::vector<int>&,
                                        const ConvergenceOptions&);

}  // namespace rrr
