// Rule 1 of VerifyChains (include/rrr/rrr/chains/verify_chains.h): the
// links of a cluster between two chains that agree with themselves.
#ifndef RRR_CORE_RRR_CHAINS_OWN_AGREEMENT_H_
#define RRR_CORE_RRR_CHAINS_OWN_AGREEMENT_H_

#include <algorithm>
#include <functional>
#include <numeric>
#include <utility>
#include <vector>

#include "rigid_fit.h"
#include "rrr/graph/chain_spans.h"
#include "rrr/graph/pose_graph.h"
#include "rrr/io/g2o.h"
#include "rrr/rrr/chi_square.h"
#include "rrr/rrr/decision_reason.h"
#include "rrr/solver/edge_error.h"
#include "rrr/solver/pose_graph_solver.h"
#include "rrr/solver/solve_in_parallel.h"

namespace rrr {

// A cluster of the loops between two chains, as rule 1 leaves it.
struct PairCluster {
  int index;               // into Verdict::clusters
  std::vector<int> links;  // indices into the pair's candidates, kept so far
  // The links rule 1 took out one at a time, with their reasons: refused
  // once the kept links are accepted, or refused as no group that agrees;
  // if the joined map refuses those, they are judged again as a cluster of
  // their own (OwnAgreement::KeepLeftOut).
  std::vector<std::pair<int, DecisionReason>> left_out;
};

// Rule 1 over the candidates between two chains: a cluster's links against
// the odometry of both chains alone (the stretches between their ends, the
// relative pose free), the link that brings most taken out while their
// error is over the gate group_scale·χ²(e·(n − 1)). That link is sought by
// leaving out in turn the links that can bring most (Suspects), a solve
// each: on a cluster of n links, up to n solves a round where every link
// is a suspect, far fewer where a few links fit worst.
template <class Pose>
class OwnAgreement {
 public:
  // Refuses candidate `link` (an index into `candidates`) for `reason`.
  using Refuse = std::function<void(int link, const DecisionReason& reason)>;

  // `candidates` index graph.loops(), each between `second` and one other
  // chain (the same for all); `estimates` are every pose's of `graph`.
  // Every reference must outlive the rule.
  OwnAgreement(const PoseGraph<Pose>& graph, const std::vector<Pose>& estimates,
               const ChainSpan& second, const std::vector<int>& candidates,
               const ChiSquareQuantile& chi2, double group_scale, int threads)
      : graph_(graph),
        estimates_(estimates),
        second_(second),
        candidates_(candidates),
        chi2_(chi2),
        group_scale_(group_scale),
        threads_(threads) {}

  // Rule 1 for `c`: returns whether links that agree remain (at least two),
  // with c->links those links and c->left_out the links taken out. If no
  // link brings more than a link's gate while the links do not agree, the
  // cluster holds no group that agrees: its links are refused (kOwn, by
  // `refuse`), and those it took out for what each brought.
  bool Keep(PairCluster* c, const Refuse& refuse) const {
    const int e = Pose::kDof;
    OwnMinimum own = Minimize(c->links);
    while (c->links.size() >= 2) {
      const int dof = e * (static_cast<int>(c->links.size()) - 1);
      const double gate = group_scale_ * chi2_(dof);
      if (own.error < gate) return true;
      // The link that brings most: the error with it minus without it (the
      // errors without each suspect solved side by side).
      const std::vector<size_t> suspects = Suspects(own);
      std::vector<OwnMinimum> without(suspects.size());
      if (c->links.size() > 2) {
        ForEachInParallel(suspects.size(), threads_, [&](size_t s) {
          std::vector<int> rest = c->links;
          rest.erase(rest.begin() + static_cast<std::ptrdiff_t>(suspects[s]));
          without[s] = Minimize(rest);
        });
      }
      double most = -1.0;
      size_t worst = 0;
      for (size_t s = 0; s < suspects.size(); ++s) {
        if (own.error - without[s].error > most) {
          most = own.error - without[s].error;
          worst = s;
        }
      }
      const double link_gate = group_scale_ * chi2_(e);
      if (most < link_gate) {
        for (const int k : c->links) {
          refuse(k, {DecisionTest::kOwn, own.error, gate, group_scale_, dof});
        }
        c->links.clear();
        for (const auto& [link, reason] : c->left_out) refuse(link, reason);
        c->left_out.clear();
        return false;
      }
      const auto at =
          c->links.begin() + static_cast<std::ptrdiff_t>(suspects[worst]);
      c->left_out.push_back(
          {*at, {DecisionTest::kOwnLink, most, link_gate, group_scale_, e}});
      c->links.erase(at);
      own = std::move(without[worst]);
    }
    return false;
  }

  // Once the joined map refuses the links of `c` that agree: the links rule
  // 1 took out of it, one at a time, become its links and are judged by
  // Keep (taking out links one at a time can keep the wrong side of a
  // cluster that mixes two groups). Returns whether links that agree remain
  // (at least two).
  bool KeepLeftOut(PairCluster* c, const Refuse& refuse) const {
    c->links.clear();
    for (const auto& taken : c->left_out) c->links.push_back(taken.first);
    c->left_out.clear();
    return c->links.size() >= 2 && Keep(c, refuse);
  }

 private:
  // The minimum of the error of some links with the odometry alone.
  struct OwnMinimum {
    PoseGraph<Pose> graph;  // Own(links)
    double error = 0.0;
    std::vector<Pose> x;  // the poses of `graph` there
  };

  // The graph of `links` with the odometry alone: the stretches of both
  // chains between their ends, loop k of it links[k]; the second stretch
  // starts at pose `*first_of_b` of it.
  PoseGraph<Pose> Own(const std::vector<int>& links,
                      int* first_of_b = nullptr) const {
    ChainSpan a{graph_.num_poses(), -1}, b = a;
    std::vector<int> loops;
    for (const int k : links) {
      loops.push_back(candidates_[k]);
      const auto& e = graph_.loops()[loops.back()];
      for (const int p : {e.from, e.to}) {
        ChainSpan& span = second_.Holds(p) ? b : a;
        span.first = std::min(span.first, p);
        span.last = std::max(span.last, p);
      }
    }
    if (first_of_b) *first_of_b = a.size();
    return SubGraph(graph_, {a, b}, estimates_, loops);
  }

  // The minimum of `links`' error with the odometry alone (Own), the
  // relative pose of the chains free, from the first link's placement.
  OwnMinimum Minimize(const std::vector<int>& links) const {
    int first_of_b = 0;
    OwnMinimum minimum;
    minimum.graph = Own(links, &first_of_b);
    const PoseGraph<Pose>& own = minimum.graph;
    const PoseGraphSolver<Pose> solver(own, 1);
    const std::vector<Pose> start =
        PlacedBy(own.loops().front(), first_of_b, solver.initial());
    MinimizeResult result;
    minimum.x =
        solver.Optimize(AllLoops(own), ConvergenceOptions{}, &result, &start);
    minimum.error = result.final_chi2;
    return minimum;
  }

  // The indices into the links of `own` (their loops, in order) of those
  // that may bring most. What a link brings is at least its d² at the
  // minimum, and to first order it is its change of the minimum
  // (PoseGraphSolver::ChangesOfMinimum; exactly so for a linear problem):
  // a link whose change is under the largest d² is not searched. Every
  // link if there are two or fewer, or if that change cannot be found.
  std::vector<size_t> Suspects(const OwnMinimum& own) const {
    const PoseGraph<Pose>& graph = own.graph;
    const size_t n = graph.loops().size();
    std::vector<size_t> all(n);
    std::iota(all.begin(), all.end(), size_t{0});
    if (n <= 2) return all;
    std::vector<std::vector<int>> groups;
    groups.reserve(n);
    for (int k = 0; k < static_cast<int>(n); ++k) groups.push_back({k});
    std::vector<double> changes;
    if (!PoseGraphSolver<Pose>(graph, 1).ChangesOfMinimum(
            AllLoops(graph), groups, own.x, &changes)) {
      return all;
    }
    size_t fits_worst = 0;
    std::vector<double> d2(n);
    for (size_t k = 0; k < n; ++k) {
      d2[k] = EdgeChi2(graph.loops()[k], own.x);
      if (d2[k] > d2[fits_worst]) fits_worst = k;
    }
    std::vector<size_t> suspects;
    for (size_t k = 0; k < n; ++k) {
      if (k == fits_worst || !(changes[k] < d2[fits_worst])) {
        suspects.push_back(k);
      }
    }
    return suspects;
  }

  const PoseGraph<Pose>& graph_;
  const std::vector<Pose>& estimates_;
  const ChainSpan second_;
  const std::vector<int>& candidates_;
  const ChiSquareQuantile& chi2_;
  const double group_scale_;
  const int threads_;  // solves side by side (RrrOptions::threads)
};

}  // namespace rrr

#endif  // RRR_CORE_RRR_CHAINS_OWN_AGREEMENT_H_
