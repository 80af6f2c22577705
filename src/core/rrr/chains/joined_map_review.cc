#include "joined_map_review.h"

#include <algorithm>
#include <map>
#include <utility>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/graph/chain_spans.h"
#include "rrr/rrr/chi_square.h"
#include "rrr/solver/pose_graph_solver.h"

namespace rrr {

namespace {

// A cluster's links in or out of one joined map as the review weighs them.
struct Weighed {
  RefutedGroup group;  // loops as indices of the map's own graph meanwhile
  bool in = true;
  bool put_back = false;
  double gate = 0.0;
};

}  // namespace

template <class Pose>
std::vector<RefutedGroup> ReviewJoinedMaps(
    const PoseGraph<Pose>& graph, const ChainsVerdict<Pose>& judged,
    const std::vector<ChainAlone<Pose>>& alone,
    const std::vector<RefutedGroup>& refuted, const RrrOptions& options,
    const std::vector<int>& chains) {
  const ChiSquareQuantile chi2(options.alpha);
  const int num_chains = static_cast<int>(judged.chains.size());
  const auto chain_of = [&](int pose) {
    return ChainHolding(judged.chains, pose);
  };
  const auto weighs = [&](int chain) {
    return chains.empty() ||
           std::binary_search(chains.begin(), chains.end(), chain);
  };
  std::vector<RefutedGroup> out;
  for (int m = 0; m < num_chains; ++m) {
    std::vector<ChainSpan> spans;
    bool weighed_here = false;
    for (int c = 0; c < num_chains; ++c) {
      if (judged.map_of_chain[c] != m) continue;
      spans.push_back(judged.chains[c]);
      weighed_here = weighed_here || weighs(c);
    }
    // A chain in no joined map has nothing to refute its clusters with.
    if (spans.size() < 2 || !weighed_here) continue;
    // The map's accepted loops, then those refuted before, as loops of its
    // own graph; its clusters inside chains, in and out.
    std::vector<int> loops;
    std::vector<Weighed> weighed;
    std::map<int, int> weighed_of_cluster;
    for (const int k : judged.verdict.accepted) {
      const auto& e = graph.loops()[k];
      const int c = chain_of(e.from);
      if (judged.map_of_chain[c] != m) continue;
      if (c == chain_of(e.to) && weighs(c)) {
        const auto [at, added] =
            weighed_of_cluster.emplace(judged.verdict.cluster_of_loop[k],
                                       static_cast<int>(weighed.size()));
        if (added) weighed.push_back({{c, {}, {}}, true});
        weighed[at->second].group.loops.push_back(
            static_cast<int>(loops.size()));
      }
      loops.push_back(k);
    }
    for (const RefutedGroup& g : refuted) {
      if (judged.map_of_chain[g.chain] != m || !weighs(g.chain)) continue;
      weighed.push_back({g, false});
      for (int& k : weighed.back().group.loops) {
        loops.push_back(k);
        k = static_cast<int>(loops.size()) - 1;
      }
    }
    for (Weighed& w : weighed) {
      const int n = static_cast<int>(w.group.loops.size());
      const MapVerifierStats& s = alone[w.group.chain].stats;
      w.group.reason.test = DecisionTest::kJoinedMap;
      w.group.reason.scale = n == 1 ? s.noise_scale : s.group_noise_scale;
      w.group.reason.dof = Pose::kDof * n;
      w.gate = w.group.reason.scale * chi2(w.group.reason.dof);
      w.group.reason.gate = w.gate;
    }
    const PoseGraph<Pose> sub = SubGraph(graph, spans, judged.estimates, loops);
    const PoseGraphSolver<Pose> solver(sub, 1);
    std::vector<Pose> x = sub.estimates();
    const auto active_loops = [&] {
      std::vector<bool> in(loops.size(), true);
      for (const Weighed& w : weighed) {
        for (const int k : w.group.loops) in[k] = w.in;
      }
      std::vector<int> active;
      for (size_t k = 0; k < loops.size(); ++k) {
        if (in[k]) active.push_back(static_cast<int>(k));
      }
      return active;
    };
    std::vector<std::vector<int>> groups;
    groups.reserve(weighed.size());
    for (const Weighed& w : weighed) groups.push_back(w.group.loops);
    for (;;) {
      std::vector<double> changes;
      if (!solver.ChangesOfMinimum(active_loops(), groups, x, &changes)) break;
      int worst = -1, best = -1;
      for (size_t g = 0; g < weighed.size(); ++g) {
        Weighed& w = weighed[g];
        w.group.reason.statistic = changes[g];
        const double ratio = changes[g] / w.gate;
        if (w.in && ratio > 1.0 &&
            (worst < 0 || ratio > changes[worst] / weighed[worst].gate)) {
          worst = static_cast<int>(g);
        }
        if (!w.in && !w.put_back && ratio < 1.0 &&
            (best < 0 || ratio < changes[best] / weighed[best].gate)) {
          best = static_cast<int>(g);
        }
      }
      if (worst >= 0) {
        weighed[worst].in = false;
      } else if (best >= 0) {
        weighed[best].in = true;
        weighed[best].put_back = true;
      } else {
        break;
      }
      x = solver.Optimize(active_loops(), ConvergenceOptions{}, nullptr, &x);
    }
    for (Weighed& w : weighed) {
      if (w.in) continue;
      for (int& k : w.group.loops) k = loops[k];
      std::sort(w.group.loops.begin(), w.group.loops.end());
      out.push_back(std::move(w.group));
    }
  }
  return out;
}

template std::vector<RefutedGroup> ReviewJoinedMaps(
    const PoseGraph<Pose2>&, const ChainsVerdict<Pose2>&,
    const std::vector<ChainAlone<Pose2>>&, const std::vector<RefutedGroup>&,
    const RrrOptions&, const std::vector<int>&);
template std::vector<RefutedGroup> ReviewJoinedMaps(
    const PoseGraph<Pose3>&, const ChainsVerdict<Pose3>&,
    const std::vector<ChainAlone<Pose3>>&, const std::vector<RefutedGroup>&,
    const RrrOptions&, const std::vector<int>&);

}  // namespace rrr
