#include "rrr/rrr/chains/verify_chains.h"

#include <algorithm>
#include <map>
#include <numeric>
#include <utility>

#include "pair_judge.h"
#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/graph/disjoint_sets.h"
#include "rrr/rrr/map/verify_with_map.h"

namespace rrr {

template <class Pose>
ChainsVerdict<Pose> VerifyChains(const PoseGraph<Pose>& graph,
                                 const RrrOptions& options,
                                 MapVerifierStats* stats) {
  ChainsVerdict<Pose> out;
  out.chains = ChainSpansOf(graph);
  const int num_chains = static_cast<int>(out.chains.size());
  out.map_of_chain.resize(num_chains);
  std::iota(out.map_of_chain.begin(), out.map_of_chain.end(), 0);
  if (num_chains <= 1) {
    out.verdict = VerifyWithMap(graph, options, &out.estimates, stats);
    return out;
  }
  Verdict& verdict = out.verdict;
  verdict.cluster_of_loop.assign(graph.loops().size(), -1);
  verdict.reasons.resize(graph.loops().size());
  out.estimates = graph.estimates();

  // The loops inside each chain, and between each pair.
  std::vector<std::vector<int>> inside(num_chains);
  std::map<std::pair<int, int>, std::vector<int>> between;
  for (size_t k = 0; k < graph.loops().size(); ++k) {
    const auto& e = graph.loops()[k];
    const int a = ChainHolding(out.chains, e.from);
    const int b = ChainHolding(out.chains, e.to);
    if (a == b) {
      inside[a].push_back(static_cast<int>(k));
    } else {
      between[{std::min(a, b), std::max(a, b)}].push_back(static_cast<int>(k));
    }
  }

  // Each chain alone, as if it were the whole graph.
  std::vector<std::vector<int>> accepted_inside(num_chains);
  std::vector<MapVerifierStats> chain_stats(num_chains);
  for (int c = 0; c < num_chains; ++c) {
    const ChainSpan& span = out.chains[c];
    const PoseGraph<Pose> alone =
        SubGraph(graph, {span}, graph.estimates(), inside[c]);
    std::vector<Pose> map;
    const Verdict v = VerifyWithMap(alone, options, &map, &chain_stats[c]);
    std::copy(map.begin(), map.end(), out.estimates.begin() + span.first);
    const int offset = static_cast<int>(verdict.clusters.size());
    for (Cluster cluster : v.clusters) {
      for (int& k : cluster.loops) k = inside[c][k];
      verdict.clusters.push_back(cluster);
    }
    for (size_t k = 0; k < inside[c].size(); ++k) {
      const int loop = inside[c][k];
      verdict.cluster_of_loop[loop] = offset + v.cluster_of_loop[k];
      DecisionReason reason = v.reasons[k];
      if (reason.pose >= 0) reason.pose += span.first;
      if (reason.by_cluster >= 0) reason.by_cluster += offset;
      verdict.reasons[loop] = reason;
    }
    for (const int k : v.accepted) {
      accepted_inside[c].push_back(inside[c][k]);
      verdict.accepted.push_back(inside[c][k]);
    }
    for (const int k : v.rejected) verdict.rejected.push_back(inside[c][k]);
  }

  // Each pair, with both chains at their own maps.
  DisjointSets maps(num_chains);  // joined chains; a map is its lowest chain
  // The pairs with the most candidates first: a pair with few may then be
  // joined through others.
  std::vector<std::pair<std::pair<int, int>, std::vector<int>>> ordered(
      between.begin(), between.end());
  std::stable_sort(ordered.begin(), ordered.end(),
                   [](const auto& x, const auto& y) {
                     return x.second.size() > y.second.size();
                   });
  for (const auto& chains_and_candidates : ordered) {
    const int a = chains_and_candidates.first.first;
    const int b = chains_and_candidates.first.second;
    ChainPair<Pose> pair;
    pair.first = a;
    pair.second = b;
    pair.candidates = chains_and_candidates.second;
    // Two chains apart: each at its own map, with its accepted loops; in one
    // map already: every chain of it in its frame, with every accepted loop.
    const int map = maps.Find(a);
    const bool one_map = map == maps.Find(b);
    const std::vector<Pose> frames = FramesIn(out.pairs, num_chains, map);
    std::vector<ChainSpan> spans;
    std::vector<Pose> placed = out.estimates;
    std::vector<int> accepted;
    for (int c = 0; c < num_chains; ++c) {
      if (one_map ? maps.Find(c) != map : c != a && c != b) continue;
      spans.push_back(out.chains[c]);
      for (int p = out.chains[c].first; one_map && p <= out.chains[c].last;
           ++p) {
        placed[p] = frames[c] * out.estimates[p];
      }
    }
    for (const int k : verdict.accepted) {
      const auto& e = graph.loops()[k];
      const int from = ChainHolding(out.chains, e.from);
      const int to = ChainHolding(out.chains, e.to);
      const auto in = [&](int c) {
        return one_map ? maps.Find(c) == map : c == a || c == b;
      };
      if (in(from) && in(to) && (one_map || from == to)) accepted.push_back(k);
    }
    PairJudge<Pose> judge(
        graph, spans, out.chains[b], placed, accepted, &pair, options,
        std::max(chain_stats[a].group_noise_scale,
                 chain_stats[b].group_noise_scale),
        std::max(chain_stats[a].noise_scale, chain_stats[b].noise_scale),
        &verdict);
    judge.Judge(one_map);
    if (one_map) pair.relative = frames[a].inverse() * frames[b];
    std::sort(pair.accepted.begin(), pair.accepted.end());
    if (pair.joined) maps.Join(a, b);
    out.pairs.push_back(std::move(pair));
  }
  std::sort(verdict.accepted.begin(), verdict.accepted.end());
  std::sort(verdict.rejected.begin(), verdict.rejected.end());
  std::sort(out.pairs.begin(), out.pairs.end(),
            [](const ChainPair<Pose>& x, const ChainPair<Pose>& y) {
              return std::make_pair(x.first, x.second) <
                     std::make_pair(y.first, y.second);
            });

  // Rule 4: each map, in the frame of its lowest chain, minimized with its
  // accepted loops.
  MinimizeMaps(graph, verdict.accepted, &out);

  if (stats) {
    *stats = MapVerifierStats();
    int largest = 0;
    for (int c = 0; c < num_chains; ++c) {
      const MapVerifierStats& s = chain_stats[c];
      stats->own_solves += s.own_solves;
      stats->trials += s.trials;
      stats->quick_accepts += s.quick_accepts;
      stats->reversals += s.reversals;
      stats->rejudged += s.rejudged;
      stats->optimizations += s.optimizations;
      stats->not_converged += s.not_converged;
      if (out.chains[c].size() > out.chains[largest].size()) largest = c;
    }
    const MapVerifierStats& s = chain_stats[largest];
    stats->noise_scale = s.noise_scale;
    stats->group_noise_scale = s.group_noise_scale;
    stats->noise_scale_source = s.noise_scale_source;
    stats->a_posteriori_scale = s.a_posteriori_scale;
  }
  return out;
}

template ChainsVerdict<Pose2> VerifyChains(const PoseGraph<Pose2>&,
                                           const RrrOptions&,
                                           MapVerifierStats*);
template ChainsVerdict<Pose3> VerifyChains(const PoseGraph<Pose3>&,
                                           const RrrOptions&,
                                           MapVerifierStats*);

}  // namespace rrr
