// The loops between two odometry chains judged by rules 1–3 of VerifyChains
// (include/rrr/rrr/chains/verify_chains.h).
#ifndef RRR_CORE_RRR_CHAINS_PAIR_JUDGE_H_
#define RRR_CORE_RRR_CHAINS_PAIR_JUDGE_H_

#include <algorithm>
#include <array>
#include <limits>
#include <map>
#include <numeric>
#include <utility>
#include <vector>

#include "rrr/graph/chain_spans.h"
#include "rrr/graph/pose_graph.h"
#include "rrr/io/g2o.h"
#include "rrr/rrr/chi_square.h"
#include "rrr/rrr/clustering.h"
#include "rrr/rrr/options.h"
#include "rrr/rrr/verdict.h"
#include "rrr/solver/chain_maps.h"
#include "rrr/solver/edge_error.h"
#include "rrr/solver/pose_graph_solver.h"

namespace rrr {

// The loops between two chains, judged by rules 1–3 of VerifyChains over a
// graph of chains: the two, each at its own map in its own frame, or every
// chain of the map they are in already; their odometry, their accepted
// loops, then the candidates.
template <class Pose>
class PairJudge {
 public:
  // A trial of links against the joined map starts at its minimum; true
  // links converge there in 2–3 iterations, while a false one bends the map
  // for 50–100 (manhattanOlson3500 cut in two). A trial stops after this
  // many and takes the error reached, which bounds the minimum from above:
  // as a trial of the map procedure held to its region, a pass is final and
  // a link that fails may be refused that a longer trial would keep.
  static constexpr int kMostTrialIterations = 5;

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
        first_of_b_(spans.front().size()),
        second_(second),
        num_inside_(static_cast<int>(accepted.size())),
        inside_(Range(0, num_inside_)),
        apart_error_(
            solver_.Evaluate(inside_, pair_graph_.estimates()).total_chi2),
        pair_(pair),
        chi2_(options.alpha),
        window_(options.cluster_window),
        group_scale_(group_scale),
        map_scale_(map_scale),
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
      clusters_.push_back({index, c.loops});
    }
  }

  // Judges the pair; `one_map`: its chains are joined through others
  // already, and their map is the joined map of rule 3.
  void Judge(bool one_map) {
    // Rule 1: each cluster's own consistency.
    std::vector<const PairCluster*> agreeing;
    for (PairCluster& c : clusters_) {
      if (c.links.size() >= 2 && KeepAgreeing(&c)) agreeing.push_back(&c);
    }
    std::stable_sort(agreeing.begin(), agreeing.end(),
                     [](const PairCluster* x, const PairCluster* y) {
                       return x->links.size() > y->links.size();
                     });
    // Rule 2: two clusters that agree join the chains.
    std::vector<Pose> joined;
    if (one_map) {
      pair_->joined = true;
      joined = Minimize({}, &brought_, &pair_graph_.estimates());
    }
    for (size_t i = 0; i < agreeing.size() && !pair_->joined; ++i) {
      const std::vector<Pose> one = Minimize(agreeing[i]->links);
      for (size_t j = 0; j < agreeing.size() && !pair_->joined; ++j) {
        if (j == i) continue;
        TryJoin(*agreeing[i], *agreeing[j], one, &joined);
      }
    }
    // Rule 3: the other clusters against the joined map; or none, apart.
    std::vector<std::vector<int>> rest;
    for (const PairCluster& c : clusters_) {
      std::vector<int> open;
      for (const int k : c.links) {
        if (!Decided(k)) open.push_back(k);
      }
      if (!open.empty()) rest.push_back(open);
    }
    if (!pair_->joined) {
      for (const auto& links : rest) {
        for (const int k : links) Decide(k, false, {DecisionTest::kApart});
      }
      return;
    }
    JudgeAgainstJoined(rest, &joined);
    // Joined through others, the pair's own loops join it if any is kept.
    if (one_map) pair_->joined = !pair_->accepted.empty();
    if (!one_map) {
      pair_->relative =
          joined[first_of_b_] * pair_graph_.estimates()[first_of_b_].inverse();
    }
  }

 private:
  struct PairCluster {
    int index;               // into verdict_->clusters
    std::vector<int> links;  // indices into pair_->candidates, kept so far
  };

  static std::vector<int> Concat(std::vector<int> x,
                                 const std::vector<int>& y) {
    x.insert(x.end(), y.begin(), y.end());
    return x;
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

  // `x` (poses of `g`, the second chain's from `first_of_b` on) with the
  // second chain moved so that the link `e` of `g` holds exactly.
  static std::vector<Pose> Placed(std::vector<Pose> x, int first_of_b,
                                  const Constraint<Pose>& e) {
    const bool from_a = e.from < first_of_b;
    const int i = from_a ? e.from : e.to;
    const int j = from_a ? e.to : e.from;
    const Pose z = from_a ? e.measurement : e.measurement.inverse();
    const Pose moved = x[i] * z * x[j].inverse();
    for (size_t p = first_of_b; p < x.size(); ++p) x[p] = moved * x[p];
    return x;
  }

  // The two maps minimized with `links` from `start` (default: both maps
  // placed by the first link); `*brought` is the error the links bring.
  std::vector<Pose> Minimize(
      const std::vector<int>& links, double* brought = nullptr,
      const std::vector<Pose>* start = nullptr,
      const ConvergenceOptions& convergence = ConvergenceOptions{}) const {
    const std::vector<Pose> placed =
        start ? *start
              : Placed(pair_graph_.estimates(), first_of_b_,
                       pair_graph_.loops()[num_inside_ + links.front()]);
    MinimizeResult result;
    std::vector<Pose> x =
        solver_.Optimize(Active(links), convergence, &result, &placed);
    // Not converged, the error reached still bounds the minimum from above.
    if (brought) *brought = result.final_chi2 - apart_error_;
    return x;
  }

  // The minimal error of `links` with the odometry alone: the stretches of
  // both chains between their ends, the relative pose free.
  double OwnError(const std::vector<int>& links) const {
    ChainSpan a{graph_.num_poses(), -1}, b = a;
    std::vector<int> loops;
    for (const int k : links) {
      loops.push_back(pair_->candidates[k]);
      const auto& e = graph_.loops()[loops.back()];
      for (const int p : {e.from, e.to}) {
        ChainSpan& span = second_.Holds(p) ? b : a;
        span.first = std::min(span.first, p);
        span.last = std::max(span.last, p);
      }
    }
    const PoseGraph<Pose> own = SubGraph(graph_, {a, b}, estimates_, loops);
    const PoseGraphSolver<Pose> solver(own, 1);
    const std::vector<Pose> start =
        Placed(solver.initial(), a.size(), own.loops().front());
    MinimizeResult result;
    solver.Optimize(AllLoops(own), ConvergenceOptions{}, &result, &start);
    return result.final_chi2;
  }

  // Rule 1 for cluster `c`; returns whether links that agree remain (at
  // least two).
  bool KeepAgreeing(PairCluster* c) {
    const int e = Pose::kDof;
    double brought = OwnError(c->links);
    while (c->links.size() >= 2) {
      const int dof = e * (static_cast<int>(c->links.size()) - 1);
      const double gate = group_scale_ * chi2_(dof);
      if (brought < gate) return true;
      // The link that brings most: the error with it minus without it.
      double most = -1.0, without_most = 0.0;
      size_t worst = 0;
      for (size_t n = 0; n < c->links.size(); ++n) {
        std::vector<int> rest = c->links;
        rest.erase(rest.begin() + n);
        const double without = rest.size() >= 2 ? OwnError(rest) : 0.0;
        if (brought - without > most) {
          most = brought - without;
          without_most = without;
          worst = n;
        }
      }
      const double link_gate = group_scale_ * chi2_(e);
      if (most < link_gate) {
        for (const int k : c->links) {
          Decide(k, false,
                 {DecisionTest::kOwn, brought, gate, group_scale_, dof});
        }
        c->links.clear();
        return false;
      }
      Decide(c->links[worst], false,
             {DecisionTest::kOwnLink, most, link_gate, group_scale_, e});
      c->links.erase(c->links.begin() + worst);
      brought = without_most;
    }
    return false;
  }

  // Whether the links `x` and `y` are separate evidence: more than a
  // clustering window apart on at least one of the chains (a revisit that
  // the clustering split in two, or one false group, is one piece of
  // evidence, however many clusters it makes).
  bool Independent(const std::vector<int>& x, const std::vector<int>& y) const {
    const auto ranges = [&](const std::vector<int>& links) {
      std::array<PoseId, 4> r{std::numeric_limits<PoseId>::max(),
                              std::numeric_limits<PoseId>::min(),
                              std::numeric_limits<PoseId>::max(),
                              std::numeric_limits<PoseId>::min()};
      for (const int k : links) {
        const auto& e = graph_.loops()[pair_->candidates[k]];
        for (const int p : {e.from, e.to}) {
          const int side = second_.Holds(p) ? 2 : 0;
          r[side] = std::min(r[side], graph_.ids()[p]);
          r[side + 1] = std::max(r[side + 1], graph_.ids()[p]);
        }
      }
      return r;
    };
    const std::array<PoseId, 4> a = ranges(x), b = ranges(y);
    for (const int side : {0, 2}) {
      const PoseId gap = std::max(b[side] - a[side + 1], a[side] - b[side + 1]);
      if (gap > window_) return true;
    }
    return false;
  }

  // Rule 2 for `first` (minimized alone to `one`) and `second`: joins the
  // chains and sets `*joined` to the joined map if they agree.
  void TryJoin(const PairCluster& first, const PairCluster& second,
               const std::vector<Pose>& one, std::vector<Pose>* joined) {
    if (!Independent(first.links, second.links)) return;
    const int e = Pose::kDof;
    const double fit_error = ErrorAt(second.links, one);
    const int n2 = static_cast<int>(second.links.size());
    if (!(fit_error < group_scale_ * chi2_(e * n2))) return;
    const std::vector<int> both = Concat(first.links, second.links);
    double brought;
    std::vector<Pose> x = Minimize(both, &brought, &one);
    const int dof = e * (static_cast<int>(both.size()) - 1);
    const double gate = group_scale_ * chi2_(dof);
    if (!(brought < gate)) return;
    pair_->joined = true;
    pair_->joined_by = {first.index, second.index};
    in_map_ = both;
    brought_ = brought;
    for (const int k : both) {
      Decide(k, true, {DecisionTest::kJoin, brought, gate, group_scale_, dof});
    }
    *joined = std::move(x);
  }

  // Rule 3 for the clusters `rest` (their open links). Every cluster whose
  // links' error at the joined map's estimate `*joined` is under their gate
  // is accepted (that error bounds what they bring) and the map minimized
  // with them, until none fits; then the best fitting one is tried (the map
  // minimized with it: accepted if what it brings is under the gate), and
  // so on until every cluster is decided.
  void JudgeAgainstJoined(const std::vector<std::vector<int>>& rest,
                          std::vector<Pose>* joined) {
    std::vector<bool> open(rest.size(), true);
    for (size_t left = rest.size(); left > 0;) {
      bool fitted = false;
      double best = std::numeric_limits<double>::infinity();
      size_t next = 0;
      for (size_t c = 0; c < rest.size(); ++c) {
        if (!open[c]) continue;
        const DecisionReason reason = FitReason(rest[c], *joined);
        if (reason.statistic < reason.gate) {
          Accept(rest[c], reason);
          open[c] = false;
          --left;
          fitted = true;
        } else if (reason.statistic / reason.gate < best) {
          best = reason.statistic / reason.gate;
          next = c;
        }
      }
      if (fitted) {
        *joined = Minimize(in_map_, &brought_, joined);
        continue;
      }
      if (left == 0) break;
      DecisionReason reason = FitReason(rest[next], *joined);
      double with;
      std::vector<Pose> x = Minimize(Concat(in_map_, rest[next]), &with, joined,
                                     {kMostTrialIterations, 1e-9});
      reason.statistic = with - brought_;
      open[next] = false;
      --left;
      if (reason.statistic < reason.gate) {
        Accept(rest[next], reason);
        *joined = std::move(x);
        brought_ = with;
      } else {
        for (const int k : rest[next]) Decide(k, false, reason);
      }
    }
  }

  void Accept(const std::vector<int>& links, const DecisionReason& reason) {
    for (const int k : links) Decide(k, true, reason);
    in_map_ = Concat(in_map_, links);
  }

  // The error of `links` at `x`.
  double ErrorAt(const std::vector<int>& links,
                 const std::vector<Pose>& x) const {
    double sum = 0.0;
    for (const int k : links) {
      sum += EdgeChi2(pair_graph_.loops()[num_inside_ + k], x);
    }
    return sum;
  }

  // The error of `links` at `x` against their gate (one link: map scale;
  // several: group scale).
  DecisionReason FitReason(const std::vector<int>& links,
                           const std::vector<Pose>& x) const {
    const int n = static_cast<int>(links.size());
    const int dof = Pose::kDof * n;
    const double scale = n == 1 ? map_scale_ : group_scale_;
    return {DecisionTest::kMap, ErrorAt(links, x), scale * chi2_(dof), scale,
            dof};
  }

  bool Decided(int k) const { return decided_.count(k) > 0; }
  void Decide(int k, bool accept, DecisionReason reason) {
    decided_[k] = accept;
    const int loop = pair_->candidates[k];
    verdict_->reasons[loop] = reason;
    (accept ? pair_->accepted : verdict_->rejected).push_back(loop);
    if (accept) verdict_->accepted.push_back(loop);
  }

  const PoseGraph<Pose>& graph_;
  const std::vector<Pose>& estimates_;
  const PoseGraph<Pose> pair_graph_;
  const PoseGraphSolver<Pose> solver_;
  const int first_of_b_;    // in pair_graph_, when it holds the two chains
  const ChainSpan second_;  // the pair's second chain, in graph_
  const int num_inside_;
  const std::vector<int> inside_;
  const double apart_error_;  // both maps, no link between them
  ChainPair<Pose>* pair_;
  const ChiSquareQuantile chi2_;
  const PoseId window_;
  const double group_scale_;
  const double map_scale_;
  Verdict* verdict_;
  std::vector<PairCluster> clusters_;
  std::map<int, bool> decided_;
  std::vector<int> in_map_;  // the links between the chains accepted so far
  double brought_ = 0.0;     // the error they bring to the two maps
};

}  // namespace rrr

#endif  // RRR_CORE_RRR_CHAINS_PAIR_JUDGE_H_
