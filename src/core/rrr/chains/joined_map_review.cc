#include "joined_map_review.h"

#include <algorithm>
#include <limits>
#include <map>
#include <utility>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/graph/chain_spans.h"
#include "rrr/rrr/chi_square.h"
#include "rrr/solver/pose_graph_solver.h"
#include "separate_evidence.h"

namespace rrr {

namespace {

// A cluster's links in or out of one joined map as the review weighs them.
struct Weighed {
  RefutedGroup group;  // loops as indices of the map's own graph meanwhile
  bool in = true;
  bool put_back = false;
  // A cluster between two chains that rule 3 refused against the map: never
  // in, evidence of a coalition only (MostOutweighed).
  bool challenger = false;
  int second_chain = -1;  // a challenger's chains: group.chain < this one
  int cluster = -1;       // a challenger's cluster in the verdict
  double gate = 0.0;
};

// Of the clusters in, the one its coalition outweighs most, or -1. The
// coalition of a cluster F is the challengers over their gates that would
// fit without F (`without[F][g]`: challenger g's change of minimum at the
// minimum without F, to first order), if they hold two clusters that are
// separate evidence (rule 2's condition for a join). Of F and its
// coalition C, the one less consistent with the other goes (RRR's
// reversal): F if Δ(F | C) / gate(F) > Δ(C | F) / gate(C) and > 1, where
// Δ(C | F) = Σ changes of C now, Δ(F | C) = Δ(F) + Δ(C | F) − Δ(C | no F)
// and gate(C) is at the largest scale of C's clusters.
template <class Pose>
int MostOutweighed(const PoseGraph<Pose>& graph,
                   const std::vector<ChainSpan>& chains,
                   std::vector<Weighed>* weighed,
                   const std::vector<double>& changes,
                   const std::vector<std::vector<double>>& without,
                   const ChiSquareQuantile& chi2, PoseId window,
                   const std::vector<int>& loops) {
  const auto loops_of = [&](const Weighed& w) {
    std::vector<int> of(w.group.loops.size());
    for (size_t n = 0; n < of.size(); ++n) of[n] = loops[w.group.loops[n]];
    return of;
  };
  int most = -1;
  double most_ratio = 1.0;
  DecisionReason reason;
  for (size_t f = 0; f < weighed->size(); ++f) {
    Weighed& outweighed = (*weighed)[f];
    if (!outweighed.in || outweighed.challenger || without[f].empty()) {
      continue;
    }
    std::vector<int> coalition;
    double now = 0.0, apart = 0.0, scale = 0.0;
    int links = 0;
    for (size_t g = 0; g < weighed->size(); ++g) {
      const Weighed& w = (*weighed)[g];
      if (!w.challenger || !(changes[g] > w.gate) ||
          !(without[f][g] <= w.gate)) {
        continue;
      }
      coalition.push_back(static_cast<int>(g));
      now += changes[g];
      apart += without[f][g];
      scale = std::max(scale, w.group.reason.scale);
      links += static_cast<int>(w.group.loops.size());
    }
    if (coalition.size() < 2) continue;
    std::vector<std::vector<int>> members;
    members.reserve(coalition.size());
    for (const int g : coalition) members.push_back(loops_of((*weighed)[g]));
    bool separate = false;
    for (size_t i = 0; i < coalition.size() && !separate; ++i) {
      for (size_t j = i + 1; j < coalition.size() && !separate; ++j) {
        const Weighed& a = (*weighed)[coalition[i]];
        const Weighed& b = (*weighed)[coalition[j]];
        separate = a.group.chain != b.group.chain ||
                   a.second_chain != b.second_chain ||
                   SeparateEvidence(graph, chains[a.second_chain], members[i],
                                    members[j], window);
      }
    }
    if (!separate) continue;
    const double ratio = (changes[f] + now - apart) / outweighed.gate;
    const double coalition_ratio = now / (scale * chi2(Pose::kDof * links));
    if (ratio > coalition_ratio && ratio > most_ratio) {
      most = static_cast<int>(f);
      most_ratio = ratio;
      // RRR's consistency indices, as kOutweighed records them; the
      // coalition's cluster that F strains most stands for it.
      int strained = coalition.front();
      for (const int g : coalition) {
        if (changes[g] > changes[strained]) strained = g;
      }
      reason = outweighed.group.reason;
      reason.test = DecisionTest::kOutweighed;
      reason.statistic = ratio;
      reason.gate = coalition_ratio;
      reason.by_cluster = (*weighed)[strained].cluster;
    }
  }
  if (most >= 0) (*weighed)[most].group.reason = reason;
  return most;
}

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
    // The clusters between its chains that rule 3 refused against it.
    std::map<int, int> challenger_of_cluster;
    for (const int k : judged.verdict.rejected) {
      const auto& e = graph.loops()[k];
      const int a = std::min(chain_of(e.from), chain_of(e.to));
      const int b = std::max(chain_of(e.from), chain_of(e.to));
      const DecisionTest test = judged.verdict.reasons[k].test;
      if (a == b || judged.map_of_chain[a] != m ||
          judged.map_of_chain[b] != m ||
          (test != DecisionTest::kMap && test != DecisionTest::kMapBound)) {
        continue;
      }
      // Every loop between chains is in a cluster of its pair.
      const int cluster = judged.verdict.cluster_of_loop[k];
      const auto [at, added] = challenger_of_cluster.emplace(
          cluster, static_cast<int>(weighed.size()));
      if (added) {
        Weighed challenger;
        challenger.group.chain = a;
        challenger.in = false;
        challenger.put_back = true;  // never put in
        challenger.challenger = true;
        challenger.second_chain = b;
        challenger.cluster = cluster;
        weighed.push_back(std::move(challenger));
      }
      weighed[at->second].group.loops.push_back(static_cast<int>(loops.size()));
      loops.push_back(k);
    }
    for (Weighed& w : weighed) {
      const int n = static_cast<int>(w.group.loops.size());
      double scale = 0.0;
      for (const int c :
           {w.group.chain, w.challenger ? w.second_chain : w.group.chain}) {
        const MapVerifierStats& s = alone[c].stats;
        scale = std::max(scale, n == 1 ? s.noise_scale : s.group_noise_scale);
      }
      w.group.reason.test = DecisionTest::kJoinedMap;
      w.group.reason.scale = scale;
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
    // The clusters inside chains, then the challengers (weighed only at the
    // coalitions); a challenger joins a coalition if it would fit: under its
    // gate.
    std::vector<std::vector<int>> groups;
    groups.reserve(weighed.size());
    std::vector<double> reach;
    for (const Weighed& w : weighed) {
      groups.push_back(w.group.loops);
      reach.push_back(w.challenger ? w.gate
                                   : std::numeric_limits<double>::infinity());
    }
    const size_t own = weighed.size() - challenger_of_cluster.size();
    const std::vector<std::vector<int>> own_groups(groups.begin(),
                                                   groups.begin() + own);
    bool challenged = false;  // at this x
    for (;;) {
      std::vector<double> changes;
      std::vector<std::vector<double>> without;
      if (!(challenged ? solver.ChangesOfMinimum(active_loops(), groups, x,
                                                 &changes, &without, reach)
                       : solver.ChangesOfMinimum(active_loops(), own_groups, x,
                                                 &changes))) {
        break;
      }
      int worst = -1, best = -1;
      for (size_t g = 0; g < own; ++g) {
        Weighed& w = weighed[g];
        if (w.group.reason.test == DecisionTest::kJoinedMap) {
          w.group.reason.statistic = changes[g];
        }
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
      } else if (!challenged && own > 0 && own < weighed.size()) {
        // Nothing left to take out or put back: the coalitions, at this x.
        challenged = true;
        continue;
      } else {
        const int f =
            challenged
                ? MostOutweighed(graph, judged.chains, &weighed, changes,
                                 without, chi2, options.cluster_window, loops)
                : -1;
        if (f < 0) break;
        weighed[f].in = false;
        weighed[f].put_back = true;
      }
      challenged = false;
      x = solver.Optimize(active_loops(), ConvergenceOptions{}, nullptr, &x);
    }
    for (Weighed& w : weighed) {
      if (w.in || w.challenger) continue;
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
