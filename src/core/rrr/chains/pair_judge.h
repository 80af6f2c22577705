// The loops between two odometry chains judged by rules 1–3 of VerifyChains
// (include/rrr/rrr/chains/verify_chains.h).
#ifndef RRR_CORE_RRR_CHAINS_PAIR_JUDGE_H_
#define RRR_CORE_RRR_CHAINS_PAIR_JUDGE_H_

#include <algorithm>
#include <limits>
#include <map>
#include <numeric>
#include <utility>
#include <vector>

#include "own_agreement.h"
#include "path_bound.h"
#include "rigid_fit.h"
#include "rrr/graph/chain_spans.h"
#include "rrr/graph/pose_graph.h"
#include "rrr/rrr/chi_square.h"
#include "rrr/rrr/clustering.h"
#include "rrr/rrr/options.h"
#include "rrr/rrr/verdict.h"
#include "rrr/solver/chain_maps.h"
#include "rrr/solver/maintained_map.h"
#include "rrr/solver/pose_graph_solver.h"
#include "separate_evidence.h"

namespace rrr {

// The loops between two chains, judged by rules 1–3 of VerifyChains over a
// graph of chains: the two, each at its own map in its own frame, or every
// chain of the map they are in already; their odometry, their accepted
// loops, then the candidates.
template <class Pose>
class PairJudge {
 public:
  // Judges the candidates of `pair` over the chains `spans` (ascending) at
  // `estimates` with their accepted loops `accepted`: the pair's two chains,
  // each at its own map, or, when they are in one map already, every chain
  // of that map placed in its frame. `verdict` receives the candidates'
  // decisions, reasons and clusters.
  PairJudge(const PoseGraph<Pose>& graph, const std::vector<ChainSpan>& spans,
            const ChainSpan& second, const std::vector<Pose>& estimates,
            const std::vector<int>& accepted, ChainPair<Pose>* pair,
            const RrrOptions& options, double group_scale, double map_scale,
            Verdict* verdict)
      : graph_(graph),
        estimates_(estimates),
        pair_graph_(SubGraph(graph, spans, estimates,
                             Concat(accepted, pair->candidates))),
        solver_(pair_graph_, 1),
        spans_(EndToEnd(spans)),
        odometry_(OdometryOf(graph, spans)),
        bound_(pair_graph_, spans, odometry_),
        first_of_b_(spans.front().size()),
        second_(second),
        num_inside_(static_cast<int>(accepted.size())),
        inside_(Range(0, num_inside_)),
        pair_(pair),
        chi2_(options.alpha),
        window_(options.cluster_window),
        radius_(options.map_radius),
        most_junctions_(options.map_junctions),
        convergence_(options.convergence),
        threads_(options.threads),
        group_scale_(group_scale),
        map_scale_(map_scale),
        own_(graph, estimates_, second_, pair->candidates, chi2_, group_scale,
             options.threads),
        verdict_(verdict) {
    Clustering clustering(options.cluster_window);
    const auto& ids = graph.ids();
    for (size_t k = 0; k < pair->candidates.size(); ++k) {
      const auto& e = graph.loops()[pair->candidates[k]];
      clustering.Add(static_cast<int>(k), ids[e.from], ids[e.to]);
    }
    for (const Cluster& c : clustering.clusters()) {
      const int index = static_cast<int>(verdict->clusters.size());
      Cluster global = c;
      global.loops.clear();
      for (const int k : c.loops) {
        global.loops.push_back(pair->candidates[k]);
        verdict->cluster_of_loop[pair->candidates[k]] = index;
      }
      verdict->clusters.push_back(global);
      clusters_.push_back({index, c.loops, {}});
    }
  }

  // Rules 1 and 2 for a pair whose chains are apart: returns the number of
  // links of the two clusters that join them (its evidence), 0 if none do.
  size_t Join() {
    const std::vector<const PairCluster*> agreeing = Agreeing();
    for (size_t i = 0; i < agreeing.size() && !pair_->joined; ++i) {
      for (size_t j = i + 1; j < agreeing.size() && !pair_->joined; ++j) {
        TryJoin(*agreeing[i], *agreeing[j]);
      }
    }
    return pair_->joined ? in_map_.size() : 0;
  }

  // Judges the pair: after Join() if its chains are apart; `one_map`: they
  // are joined through others already (rule 1, then rule 3 against that
  // map).
  void Judge(bool one_map) {
    if (one_map) {
      Agreeing();
      pair_->joined = true;
      joined_ = Minimize({}, pair_graph_.estimates());
    }
    // Rule 3: the other clusters against the joined map; or none, apart.
    if (!pair_->joined) {
      for (const PairCluster& c : clusters_) {
        for (const int k : Open(c)) Decide(k, false, {DecisionTest::kApart});
      }
      RefuseLeftOut();
      return;
    }
    JudgeAgainstJoined();
    RefuseLeftOut();
    // Joined through others, the pair's own loops join it if any is kept.
    if (one_map) pair_->joined = !pair_->accepted.empty();
    if (!one_map) {
      pair_->relative =
          joined_[first_of_b_] * pair_graph_.estimates()[first_of_b_].inverse();
    }
  }

 private:
  // Rule 1: the clusters of at least two links that agree with themselves,
  // largest first.
  std::vector<const PairCluster*> Agreeing() {
    std::vector<const PairCluster*> agreeing;
    for (PairCluster& c : clusters_) {
      if (c.links.size() >= 2 && own_.Keep(&c, Refusal())) {
        agreeing.push_back(&c);
      }
    }
    std::stable_sort(agreeing.begin(), agreeing.end(),
                     [](const PairCluster* x, const PairCluster* y) {
                       return x->links.size() > y->links.size();
                     });
    return agreeing;
  }

  static std::vector<int> Concat(std::vector<int> x,
                                 const std::vector<int>& y) {
    x.insert(x.end(), y.begin(), y.end());
    return x;
  }
  // `spans` laid end to end from pose 0, as in the pair graph.
  static std::vector<ChainSpan> EndToEnd(std::vector<ChainSpan> spans) {
    int first = 0;
    for (ChainSpan& span : spans) {
      span = {first, first + span.size() - 1};
      first = span.last + 1;
    }
    return spans;
  }
  static std::vector<int> Range(int begin, int end) {
    std::vector<int> r(end - begin);
    std::iota(r.begin(), r.end(), begin);
    return r;
  }

  // Loop indices of the pair graph: the accepted loops inside, then `links`.
  std::vector<int> Active(const std::vector<int>& links) const {
    return Concat(inside_, Links(links));
  }
  std::vector<int> Links(const std::vector<int>& links) const {
    std::vector<int> out(links.size());
    for (size_t n = 0; n < links.size(); ++n) out[n] = num_inside_ + links[n];
    return out;
  }
  // Loop indices of graph_ of `links`.
  std::vector<int> Candidates(const std::vector<int>& links) const {
    std::vector<int> out(links.size());
    for (size_t n = 0; n < links.size(); ++n) {
      out[n] = pair_->candidates[links[n]];
    }
    return out;
  }

  // The chains' maps minimized with their loops and `links` from `start`.
  std::vector<Pose> Minimize(const std::vector<int>& links,
                             const std::vector<Pose>& start) const {
    MinimizeResult result;
    return solver_.Optimize(Active(links), ConvergenceOptions{}, &result,
                            &start);
  }

  // Refuses, with the reasons rule 1 gave, the links it took out that are
  // still to be judged: their cluster's kept links were accepted, or the
  // chains stay apart.
  void RefuseLeftOut() {
    for (PairCluster& c : clusters_) {
      for (const auto& [k, reason] : c.left_out) Decide(k, false, reason);
      c.left_out.clear();
    }
  }

  // Rule 2 for `first` and `second`: joins the chains and sets joined_ to
  // the joined map if they agree on one placement of the second chain's
  // map in the first's frame (RigidFit: no bending of either map, which
  // could make far-apart clusters agree by absorbing the difference in
  // their drift).
  void TryJoin(const PairCluster& first, const PairCluster& second) {
    if (!SeparateEvidence(graph_, second_, Candidates(first.links),
                          Candidates(second.links), window_)) {
      return;
    }
    const std::vector<int> both = Concat(first.links, second.links);
    const int dof = Pose::kDof * (static_cast<int>(both.size()) - 1);
    const double gate = group_scale_ * chi2_(dof);
    Pose relative;
    const double rigid =
        RigidFit(pair_graph_, Links(both), first_of_b_, &relative);
    if (!(rigid < gate)) return;
    std::vector<Pose> start = pair_graph_.estimates();
    for (size_t p = first_of_b_; p < start.size(); ++p) {
      start[p] = relative * start[p];
    }
    pair_->joined = true;
    pair_->joined_by = {first.index, second.index};
    in_map_ = both;
    joined_ = Minimize(both, start);
    for (const int k : both) {
      Decide(k, true, {DecisionTest::kJoin, rigid, gate, group_scale_, dof});
    }
  }

  // Rule 3 for the clusters with open links (those links), against the joined
  // map held as the map procedure holds a chain (MaintainedMap), from its
  // minimum joined_. Every cluster whose links' error at the map's estimate
  // is under their gate is accepted (that error bounds what they bring) and
  // the map minimized near them, until none fits; then the best fitting one
  // is tried over the poses near its ends (widened for several links): Δ
  // over a region bounds the whole map's from above, so it is accepted if Δ
  // is under the gate. Both bounds hold at the map's minimum: a cluster is
  // refused (by the lower bound or its trial) only there, the whole map
  // minimized first if it took links since; and so on until every cluster
  // is decided. joined_ is then the map's estimate.
  //
  // When a cluster is refused, the links rule 1 took out of it are judged
  // next (OwnAgreement::KeepLeftOut), if any.
  void JudgeAgainstJoined() {
    std::vector<std::vector<int>> rest;
    std::vector<size_t> cluster_of;  // rest[i] is of clusters_[cluster_of[i]]
    for (size_t c = 0; c < clusters_.size(); ++c) {
      std::vector<int> links = Open(clusters_[c]);
      if (links.empty()) continue;
      rest.push_back(std::move(links));
      cluster_of.push_back(c);
    }
    MaintainedMap<Pose> map(pair_graph_, spans_, odometry_, convergence_,
                            most_junctions_);
    map.AddAt(Active(in_map_), joined_);
    bool at_minimum = true;
    const double significant = map_scale_ * Pose::kDof;
    std::vector<bool> open(rest.size(), true);
    for (size_t left = rest.size(); left > 0;) {
      std::vector<int> fitted;
      double best = std::numeric_limits<double>::infinity();
      size_t next = 0;
      DecisionReason reason;  // of `next`
      for (size_t c = 0; c < rest.size(); ++c) {
        if (!open[c]) continue;
        const DecisionReason fit = FitReason(rest[c], map);
        if (fit.statistic < fit.gate) {
          Accept(rest[c], fit);
          const std::vector<int> links = Links(rest[c]);
          fitted.insert(fitted.end(), links.begin(), links.end());
          open[c] = false;
          --left;
        } else if (fit.statistic / fit.gate < best) {
          best = fit.statistic / fit.gate;
          next = c;
          reason = fit;
        }
      }
      if (!fitted.empty()) {
        map.Add(fitted, radius_, significant);
        at_minimum = false;
        continue;
      }
      if (left == 0) break;
      const double least = LeastBrought(rest[next], map);
      const std::vector<int> links = Links(rest[next]);
      const auto passes = [&](const MapTrial& trial) {
        return trial.minimize.solved && trial.increase < reason.gate;
      };
      MapTrial trial;
      if (least < reason.gate) {
        trial = map.Try(links, radius_);
        if (links.size() > 1) {
          int tries = 0;
          trial = map.Widen(trial, links, radius_, reason.gate, significant,
                            passes, &tries);
        }
      }
      if (least < reason.gate && passes(trial)) {
        reason.statistic = trial.increase;
        Accept(rest[next], reason);
        map.KeepTrial(significant);
        at_minimum = false;
      } else if (!at_minimum) {
        map.Optimize();
        at_minimum = true;
        continue;
      } else {
        if (least >= reason.gate) {
          reason.test = DecisionTest::kMapBound;
          reason.statistic = least;
        } else {
          reason.statistic = trial.increase;
        }
        for (const int k : rest[next]) Decide(k, false, reason);
        PairCluster& refused = clusters_[cluster_of[next]];
        if (!refused.left_out.empty()) {
          own_.KeepLeftOut(&refused, Refusal());
          std::vector<int> links = Open(refused);
          if (!links.empty()) {
            rest.push_back(std::move(links));
            cluster_of.push_back(cluster_of[next]);
            open.push_back(true);
            ++left;
          }
        }
      }
      open[next] = false;
      --left;
    }
    joined_ = map.Estimates(threads_);
  }

  // A lower bound of what `links` would bring to the joined map, at its
  // minimum, the estimate of `map` (PathBound), through the accepted loops
  // between chains.
  double LeastBrought(const std::vector<int>& links,
                      const MaintainedMap<Pose>& map) const {
    std::vector<int> hops = Links(in_map_);
    for (const int k : inside_) {
      const auto& e = pair_graph_.loops()[k];
      if (!bound_.SameChain(e.from, e.to)) hops.push_back(k);
    }
    return bound_.Least(Links(links), hops,
                        [&](int pose) { return map.Estimate(pose); });
  }

  void Accept(const std::vector<int>& links, const DecisionReason& reason) {
    for (const int k : links) Decide(k, true, reason);
    in_map_ = Concat(in_map_, links);
  }

  // The error of `links` at the estimate of `map` against their gate (one
  // link: map scale; several: group scale).
  DecisionReason FitReason(const std::vector<int>& links,
                           const MaintainedMap<Pose>& map) const {
    const int n = static_cast<int>(links.size());
    const int dof = Pose::kDof * n;
    const double scale = n == 1 ? map_scale_ : group_scale_;
    double error = 0.0;
    for (const int k : links) error += map.LoopChi2(num_inside_ + k);
    return {DecisionTest::kMap, error, scale * chi2_(dof), scale, dof};
  }

  bool Decided(int k) const { return decided_.count(k) > 0; }
  // The links of `c` not decided yet.
  std::vector<int> Open(const PairCluster& c) const {
    std::vector<int> open;
    for (const int k : c.links) {
      if (!Decided(k)) open.push_back(k);
    }
    return open;
  }
  typename OwnAgreement<Pose>::Refuse Refusal() {
    return [this](int k, const DecisionReason& reason) {
      Decide(k, false, reason);
    };
  }
  void Decide(int k, bool accept, DecisionReason reason) {
    decided_[k] = accept;
    const int loop = pair_->candidates[k];
    verdict_->reasons[loop] = reason;
    (accept ? pair_->accepted : verdict_->rejected).push_back(loop);
    if (accept) verdict_->accepted.push_back(loop);
  }

  const PoseGraph<Pose>& graph_;
  const std::vector<Pose> estimates_;  // of every pose of graph_
  const PoseGraph<Pose> pair_graph_;
  const PoseGraphSolver<Pose> solver_;
  const std::vector<ChainSpan> spans_;  // the chains in pair_graph_
  const std::vector<OdometryChain<Pose>> odometry_;  // of each of spans_
  const PathBound<Pose> bound_;
  const int first_of_b_;    // in pair_graph_, when it holds the two chains
  const ChainSpan second_;  // the pair's second chain, in graph_
  const int num_inside_;
  const std::vector<int> inside_;
  ChainPair<Pose>* pair_;
  const ChiSquareQuantile chi2_;
  const PoseId window_;
  const int radius_;
  const int most_junctions_;
  const ConvergenceOptions convergence_;
  const int threads_;  // solves side by side (RrrOptions::threads)
  const double group_scale_;
  const double map_scale_;
  const OwnAgreement<Pose> own_;  // rule 1
  Verdict* verdict_;
  std::vector<PairCluster> clusters_;
  std::map<int, bool> decided_;
  std::vector<int> in_map_;   // the links between the chains accepted so far
  std::vector<Pose> joined_;  // the joined map, once joined
};

}  // namespace rrr

#endif  // RRR_CORE_RRR_CHAINS_PAIR_JUDGE_H_
