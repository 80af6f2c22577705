#include "rrr/rrr/chains/verify_chains.h"

#include <algorithm>
#include <map>
#include <numeric>
#include <set>
#include <tuple>
#include <utility>

#include "joined_map_review.h"
#include "pair_judge.h"
#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/graph/disjoint_sets.h"
#include "rrr/rrr/map/verify_with_map.h"
#include "rrr/solver/solve_in_parallel.h"

namespace rrr {

namespace {

// Chain `span` of `graph` judged alone by the map procedure, as if it were
// the whole graph, without the loops `left_out` (ascending).
template <class Pose>
ChainAlone<Pose> JudgeAlone(const PoseGraph<Pose>& graph, const ChainSpan& span,
                            const std::vector<int>& left_out,
                            const RrrOptions& options) {
  ChainAlone<Pose> alone;
  for (size_t k = 0; k < graph.loops().size(); ++k) {
    const auto& e = graph.loops()[k];
    if (span.Holds(e.from) && span.Holds(e.to) &&
        !std::binary_search(left_out.begin(), left_out.end(),
                            static_cast<int>(k))) {
      alone.inside.push_back(static_cast<int>(k));
    }
  }
  const PoseGraph<Pose> one =
      SubGraph(graph, {span}, graph.estimates(), alone.inside);
  alone.verdict = VerifyWithMap(one, options, &alone.map, &alone.stats);
  return alone;
}

}  // namespace

template <class Pose>
ChainsVerdict<Pose> VerifyChains(const PoseGraph<Pose>& graph,
                                 const RrrOptions& options,
                                 MapVerifierStats* stats) {
  const std::vector<ChainSpan> chains = ChainSpansOf(graph);
  if (chains.size() <= 1) {
    ChainsVerdict<Pose> out;
    out.chains = chains;
    out.map_of_chain.assign(chains.size(), 0);
    out.verdict = VerifyWithMap(graph, options, &out.estimates, stats);
    return out;
  }
  // Each chain alone, as if it were the whole graph (side by side).
  std::vector<ChainAlone<Pose>> alone(chains.size());
  ForEachInParallel(chains.size(), options.threads, [&](size_t c) {
    alone[c] = JudgeAlone(graph, chains[c], {}, options);
  });
  return JudgeChains(graph, std::move(alone), options, stats);
}

template <class Pose>
ChainsVerdict<Pose> JudgeChains(const PoseGraph<Pose>& graph,
                                std::vector<ChainAlone<Pose>> alone,
                                const RrrOptions& options,
                                MapVerifierStats* stats) {
  const std::vector<ChainSpan> chains = ChainSpansOf(graph);
  // The loops rule 5 refuted, with the sets of them already judged (rules
  // 1–5 over chains judged alone without those loops), so that the rounds
  // end even were rule 5 to come back to a set.
  std::vector<RefutedGroup> refuted;
  std::set<std::vector<int>> tried;
  const auto loops_of = [](const std::vector<RefutedGroup>& groups) {
    std::vector<int> loops;
    for (const RefutedGroup& g : groups) {
      loops.insert(loops.end(), g.loops.begin(), g.loops.end());
    }
    std::sort(loops.begin(), loops.end());
    return loops;
  };
  for (;;) {
    tried.insert(loops_of(refuted));
    // Rule 5 on the clusters of each chain as it is first joined, while
    // pairs remain: one it refutes there starts the next round at once, so
    // the pairs left are not judged against the map that cluster bent.
    std::vector<RefutedGroup> next;
    bool ended_early = false;
    std::vector<bool> joined_before(chains.size(), false);
    const AfterJoin<Pose> review_join = [&](ChainsVerdict<Pose>* joined,
                                            int map) {
      std::vector<int> newly;
      for (size_t c = 0; c < chains.size(); ++c) {
        if (joined->map_of_chain[c] != map || joined_before[c]) continue;
        newly.push_back(static_cast<int>(c));
        joined_before[c] = true;
      }
      if (newly.empty()) return false;
      MinimizeMaps(graph, joined->verdict.accepted, joined, map);
      std::vector<RefutedGroup> groups =
          ReviewJoinedMaps(graph, *joined, alone, refuted, options, newly);
      for (const RefutedGroup& g : refuted) {
        if (!std::binary_search(newly.begin(), newly.end(), g.chain)) {
          groups.push_back(g);
        }
      }
      if (tried.count(loops_of(groups))) return false;
      next = std::move(groups);
      ended_early = true;
      return true;
    };
    ChainsVerdict<Pose> out =
        JudgeBetweenChains(graph, alone, options, stats, review_join);
    if (!ended_early) {
      // Rule 4: each map, in the frame of its lowest chain, minimized with
      // its accepted loops; then rule 5 over every joined map.
      MinimizeMaps(graph, out.verdict.accepted, &out);
      next = ReviewJoinedMaps(graph, out, alone, refuted, options);
      const std::vector<int> next_loops = loops_of(next);
      if (tried.count(next_loops)) {
        // The groups as last weighed if the same loops, else as refuted.
        if (next_loops == loops_of(refuted)) refuted = std::move(next);
        for (const RefutedGroup& g : refuted) {
          for (const int k : g.loops) {
            out.verdict.rejected.push_back(k);
            out.verdict.reasons[k] = g.reason;
          }
        }
        std::sort(out.verdict.rejected.begin(), out.verdict.rejected.end());
        return out;
      }
    }
    // Each chain whose refuted loops changed, judged alone again without
    // them.
    const std::vector<int> before = loops_of(refuted);
    const std::vector<int> now = loops_of(next);
    refuted = std::move(next);
    ForEachInParallel(chains.size(), options.threads, [&](size_t c) {
      const auto of_chain = [&](const std::vector<int>& loops) {
        std::vector<int> in;
        for (const int k : loops) {
          if (chains[c].Holds(graph.loops()[k].from)) in.push_back(k);
        }
        return in;
      };
      const std::vector<int> left_out = of_chain(now);
      if (of_chain(before) == left_out) return;
      alone[c] = JudgeAlone(graph, chains[c], left_out, options);
    });
  }
}

template <class Pose>
ChainsVerdict<Pose> JudgeBetweenChains(
    const PoseGraph<Pose>& graph, const std::vector<ChainAlone<Pose>>& alone,
    const RrrOptions& options, MapVerifierStats* stats,
    const AfterJoin<Pose>& after_join) {
  ChainsVerdict<Pose> out;
  out.chains = ChainSpansOf(graph);
  const int num_chains = static_cast<int>(out.chains.size());
  Verdict& verdict = out.verdict;
  verdict.cluster_of_loop.assign(graph.loops().size(), -1);
  verdict.reasons.resize(graph.loops().size());
  out.estimates = graph.estimates();

  // The loops between each pair.
  std::map<std::pair<int, int>, std::vector<int>> between;
  for (size_t k = 0; k < graph.loops().size(); ++k) {
    const auto& e = graph.loops()[k];
    const int a = ChainHolding(out.chains, e.from);
    const int b = ChainHolding(out.chains, e.to);
    if (a != b) {
      between[{std::min(a, b), std::max(a, b)}].push_back(static_cast<int>(k));
    }
  }

  // Each chain's own decisions, and its map in its own frame.
  for (int c = 0; c < num_chains; ++c) {
    const ChainSpan& span = out.chains[c];
    const std::vector<int>& inside = alone[c].inside;
    const Verdict& v = alone[c].verdict;
    std::copy(alone[c].map.begin(), alone[c].map.end(),
              out.estimates.begin() + span.first);
    const int offset = static_cast<int>(verdict.clusters.size());
    for (Cluster cluster : v.clusters) {
      for (int& k : cluster.loops) k = inside[k];
      verdict.clusters.push_back(cluster);
    }
    for (size_t k = 0; k < inside.size(); ++k) {
      const int loop = inside[k];
      verdict.cluster_of_loop[loop] =
          v.cluster_of_loop[k] < 0 ? -1 : offset + v.cluster_of_loop[k];
      DecisionReason reason = v.reasons[k];
      if (reason.pose >= 0) reason.pose += span.first;
      if (reason.by_cluster >= 0) reason.by_cluster += offset;
      verdict.reasons[loop] = reason;
    }
    for (const int k : v.accepted) verdict.accepted.push_back(inside[k]);
    for (const int k : v.rejected) verdict.rejected.push_back(inside[k]);
  }

  // The judge of the pair of chains a < b with `candidates`: both at their
  // own maps, with their accepted loops; or, if `frames` is given (each
  // chain's frame in their map's), every chain `in_map` in its frame with
  // every accepted loop of the map.
  DisjointSets maps(num_chains);  // joined chains; a map is its lowest chain
  const auto judge_of = [&](ChainPair<Pose>* pair,
                            const std::vector<Pose>* frames, Verdict* v) {
    const int a = pair->first, b = pair->second;
    const auto in = [&](int c) {
      return frames ? maps.Find(c) == maps.Find(a) : c == a || c == b;
    };
    std::vector<ChainSpan> spans;
    std::vector<Pose> placed = out.estimates;
    for (int c = 0; c < num_chains; ++c) {
      if (!in(c)) continue;
      spans.push_back(out.chains[c]);
      for (int p = out.chains[c].first; frames && p <= out.chains[c].last;
           ++p) {
        placed[p] = (*frames)[c] * out.estimates[p];
      }
    }
    std::vector<int> accepted;
    for (const int k : verdict.accepted) {
      const auto& e = graph.loops()[k];
      const int from = ChainHolding(out.chains, e.from);
      const int to = ChainHolding(out.chains, e.to);
      if (in(from) && in(to) && (frames || from == to)) accepted.push_back(k);
    }
    return PairJudge<Pose>(
        graph, spans, out.chains[b], placed, accepted, pair, options,
        std::max(alone[a].stats.group_noise_scale,
                 alone[b].stats.group_noise_scale),
        std::max(alone[a].stats.noise_scale, alone[b].stats.noise_scale), v);
  };

  // The pairs in order of the evidence that would join them apart (rules
  // 1–2: the links of the two clusters that join them), most first, then of
  // their candidates: a join on more evidence is made first, and a pair
  // whose chains it puts in one map with others is judged against that map
  // (rule 3), so that a weaker join that contradicts it is refused instead
  // of deciding against it.
  std::vector<std::tuple<size_t, ChainPair<Pose>>> ordered;
  for (const auto& [chains, candidates] : between) {
    ChainPair<Pose> pair;
    pair.first = chains.first;
    pair.second = chains.second;
    pair.candidates = candidates;
    ChainPair<Pose> trial = pair;
    Verdict scratch;
    scratch.cluster_of_loop.resize(graph.loops().size());
    scratch.reasons.resize(graph.loops().size());
    ordered.emplace_back(judge_of(&trial, nullptr, &scratch).Join(),
                         std::move(pair));
  }
  std::stable_sort(ordered.begin(), ordered.end(),
                   [](const auto& x, const auto& y) {
                     const auto& [ex, px] = x;
                     const auto& [ey, py] = y;
                     return std::make_pair(ex, px.candidates.size()) >
                            std::make_pair(ey, py.candidates.size());
                   });
  for (auto& [evidence, pair] : ordered) {
    const int a = pair.first, b = pair.second;
    const int map = maps.Find(a);
    if (map == maps.Find(b)) {
      const std::vector<Pose> frames = FramesIn(out.pairs, num_chains, map);
      judge_of(&pair, &frames, &verdict).Judge(true);
      pair.relative = frames[a].inverse() * frames[b];
    } else {
      PairJudge<Pose> judge = judge_of(&pair, nullptr, &verdict);
      judge.Join();
      judge.Judge(false);
    }
    std::sort(pair.accepted.begin(), pair.accepted.end());
    // Two maps joined, and pairs left to judge.
    const bool review = pair.joined && map != maps.Find(b) &&
                        &pair != &std::get<1>(ordered.back());
    if (pair.joined) maps.Join(a, b);
    out.pairs.push_back(std::move(pair));
    if (review && after_join) {
      ChainsVerdict<Pose> so_far = out;
      std::sort(so_far.verdict.accepted.begin(), so_far.verdict.accepted.end());
      so_far.map_of_chain.resize(num_chains);
      for (int c = 0; c < num_chains; ++c) {
        so_far.map_of_chain[c] = maps.Find(c);
      }
      if (after_join(&so_far, maps.Find(a))) return so_far;
    }
  }
  std::sort(verdict.accepted.begin(), verdict.accepted.end());
  std::sort(verdict.rejected.begin(), verdict.rejected.end());
  std::sort(out.pairs.begin(), out.pairs.end(),
            [](const ChainPair<Pose>& x, const ChainPair<Pose>& y) {
              return std::make_pair(x.first, x.second) <
                     std::make_pair(y.first, y.second);
            });

  out.map_of_chain.resize(num_chains);
  for (int c = 0; c < num_chains; ++c) out.map_of_chain[c] = maps.Find(c);

  if (stats) {
    *stats = MapVerifierStats();
    int largest = 0;
    for (int c = 0; c < num_chains; ++c) {
      const MapVerifierStats& s = alone[c].stats;
      stats->own_solves += s.own_solves;
      stats->trials += s.trials;
      stats->quick_accepts += s.quick_accepts;
      stats->reversals += s.reversals;
      stats->rejudged += s.rejudged;
      stats->optimizations += s.optimizations;
      stats->not_converged += s.not_converged;
      if (out.chains[c].size() > out.chains[largest].size()) largest = c;
    }
    const MapVerifierStats& s = alone[largest].stats;
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
template ChainsVerdict<Pose2> JudgeChains(const PoseGraph<Pose2>&,
                                          std::vector<ChainAlone<Pose2>>,
                                          const RrrOptions&, MapVerifierStats*);
template ChainsVerdict<Pose3> JudgeChains(const PoseGraph<Pose3>&,
                                          std::vector<ChainAlone<Pose3>>,
                                          const RrrOptions&, MapVerifierStats*);
template ChainsVerdict<Pose2> JudgeBetweenChains(
    const PoseGraph<Pose2>&, const std::vector<ChainAlone<Pose2>>&,
    const RrrOptions&, MapVerifierStats*, const AfterJoin<Pose2>&);
template ChainsVerdict<Pose3> JudgeBetweenChains(
    const PoseGraph<Pose3>&, const std::vector<ChainAlone<Pose3>>&,
    const RrrOptions&, MapVerifierStats*, const AfterJoin<Pose3>&);

}  // namespace rrr
