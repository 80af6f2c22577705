// A noisy pose chain with loops, for solver and map tests.
#ifndef RRR_CORE_TESTING_NOISY_CHAIN_H_
#define RRR_CORE_TESTING_NOISY_CHAIN_H_

#include <random>
#include <utility>
#include <vector>

#include "rrr/graph/pose_graph.h"

namespace rrr::testing {

// `n` poses turning slowly, odometry and loops between the listed pairs
// (a, b), every measurement the truth perturbed by N(0, noise) in each
// tangent coordinate, with information I / noise². The first pose's
// estimate is the truth; the others are the truth too (callers start solves
// from odometry).
template <class Pose>
PoseGraph<Pose> NoisyChain(int n, const std::vector<std::pair<int, int>>& ab,
                           double noise, unsigned seed = 11) {
  constexpr int D = Pose::kDof;
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, noise);
  std::vector<Pose> truth(n);
  for (int k = 1; k < n; ++k) {
    typename Pose::Tangent xi = Pose::Tangent::Zero();
    xi[0] = 1.0;
    xi[D - 1] = 0.05;
    truth[k] = truth[k - 1] * Pose::Exp(xi);
  }
  const auto noisy = [&](const Pose& z) {
    typename Pose::Tangent e;
    for (int a = 0; a < D; ++a) e[a] = normal(rng);
    return z * Pose::Exp(e);
  };
  const typename Constraint<Pose>::Information info =
      Constraint<Pose>::Information::Identity() / (noise * noise);
  PoseGraph<Pose> graph;
  for (int k = 0; k < n; ++k) graph.AddPose(k, truth[k]);
  for (int k = 0; k + 1 < n; ++k) {
    graph.AddEdge({k, k + 1, noisy(truth[k].between(truth[k + 1])), info});
  }
  for (const auto& [a, b] : ab) {
    graph.AddEdge({a, b, noisy(truth[a].between(truth[b])), info});
  }
  return graph;
}

// `graph` with `edit(&edge, is_loop)` applied to each edge; the poses and
// their estimates as they are.
template <class Pose, class Edit>
PoseGraph<Pose> WithEachEdge(const PoseGraph<Pose>& graph, Edit edit) {
  PoseGraph<Pose> out;
  for (int k = 0; k < graph.num_poses(); ++k) {
    out.AddPose(graph.ids()[k], graph.estimates()[k]);
  }
  for (const auto* edges : {&graph.odometry(), &graph.loops()}) {
    for (Constraint<Pose> e : *edges) {
      edit(&e, edges == &graph.loops());
      out.AddEdge(e);
    }
  }
  return out;
}

// A NoisyChain of 600 poses (noise 0.01) with five true loops, graph loops
// 0 to 4, and one false loop, graph loop 5: from pose 200 to pose 500,
// measured as the identity.
template <class Pose>
PoseGraph<Pose> ChainWithOneFalseLoop() {
  PoseGraph<Pose> graph = NoisyChain<Pose>(
      600, {{10, 136}, {12, 138}, {140, 266}, {150, 276}, {270, 396}}, 0.01);
  Constraint<Pose> wrong = graph.loops()[0];
  wrong.from = 200;
  wrong.to = 500;
  wrong.measurement = Pose();
  graph.AddEdge(wrong);
  return graph;
}

}  // namespace rrr::testing

#endif  // RRR_CORE_TESTING_NOISY_CHAIN_H_
