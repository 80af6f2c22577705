#include "rrr/rrr/published/consistency_tests.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>

#include "rrr/solver/solve_in_parallel.h"

namespace rrr {
namespace {

// Loops of the listed clusters, concatenated in list order.
std::vector<int> LinksOf(const std::vector<std::vector<int>>& clusters,
                         const std::vector<int>& which) {
  std::vector<int> links;
  for (const int c : which) {
    links.insert(links.end(), clusters[c].begin(), clusters[c].end());
  }
  return links;
}

// CI_c = Σ_{l∈c} d²_l / χ²(α, e·|c|) for each cluster c of `which`, whose
// links follow one another in `loop_chi2` from `offset` on, in list order.
std::vector<double> ConsistencyIndices(
    const std::vector<double>& loop_chi2, size_t offset,
    const std::vector<std::vector<int>>& clusters,
    const std::vector<int>& which, int residual_dim,
    const ChiSquareQuantile& chi2) {
  std::vector<double> ci;
  ci.reserve(which.size());
  for (const int c : which) {
    const auto first = loop_chi2.begin() + offset;
    const int size = static_cast<int>(clusters[c].size());
    ci.push_back(std::accumulate(first, first + size, 0.0) /
                 chi2(residual_dim * size));
    offset += clusters[c].size();
  }
  return ci;
}

// The clusters of `which` (ci[k] belongs to which[k]) by decreasing CI, ties
// in list order; NaN counts as largest. With `removed` >= 0, `which` has
// already lost its element at that index, which `ci` still holds.
std::vector<int> ByDecreasingIndex(const std::vector<int>& which,
                                   std::vector<double> ci, int removed = -1) {
  if (removed >= 0) ci.erase(ci.begin() + removed);
  std::vector<int> order(which.size());
  std::iota(order.begin(), order.end(), 0);
  for (double& v : ci) {
    if (std::isnan(v)) v = std::numeric_limits<double>::infinity();
  }
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return ci[a] > ci[b]; });
  for (int& k : order) k = which[k];
  return order;
}

// The joint solves of step 3 for one set `good`: the errors of good ∪ H for
// each H the procedure reaches. With several threads, each solve that is not
// known yet is made together with the solves of the sets that follow if the
// clusters likely to be set aside next are, in that order. Which of them the
// procedure uses is decided by their errors alone, so the decisions are those
// of solving one set at a time.
class JointSolves {
 public:
  // A guess k set-asides ahead holds about 0.5^k of the time (manhattan +
  // 100, BENCHMARKS.md), and each solve running holds its own factor.
  static constexpr size_t kMostJointSolvesAtOnce = 4;

  JointSolves(const std::vector<std::vector<int>>& clusters,
              const std::vector<int>& good, ConsistencySolver& solver,
              int threads)
      : clusters_(clusters),
        good_(good),
        solver_(solver),
        threads_(static_cast<size_t>(threads)) {}

  // Errors of solving the links of good ∪ h (good's first). `likely` lists
  // clusters of h in the order they are likely to be set aside.
  const SubsetErrors& Get(const std::vector<int>& h,
                          const std::vector<int>& likely) {
    const auto known = solved_.find(h);
    if (known != solved_.end()) return known->second;
    std::vector<std::vector<int>> sets{h};
    const size_t at_once = std::min(threads_, kMostJointSolvesAtOnce);
    for (size_t k = 0; k < likely.size() && sets.size() < at_once; ++k) {
      std::vector<int> next = sets.back();
      next.erase(std::find(next.begin(), next.end(), likely[k]));
      if (next.empty()) break;
      sets.push_back(std::move(next));
    }
    std::vector<std::vector<int>> links;
    for (const auto& set : sets) {
      std::vector<int> joint = good_;
      joint.insert(joint.end(), set.begin(), set.end());
      links.push_back(LinksOf(clusters_, joint));
    }
    std::vector<SubsetErrors> errors =
        SolveInParallel(solver_, links, static_cast<int>(sets.size()));
    solved_.clear();
    for (size_t k = 0; k < sets.size(); ++k) {
      solved_.emplace(std::move(sets[k]), std::move(errors[k]));
    }
    return solved_.at(h);
  }

 private:
  const std::vector<std::vector<int>>& clusters_;
  const std::vector<int>& good_;
  ConsistencySolver& solver_;
  size_t threads_;
  std::map<std::vector<int>, SubsetErrors> solved_;
};

}  // namespace

bool TotalErrorConsistent(const SubsetErrors& errors, int residual_dim,
                          const ChiSquareQuantile& chi2, bool span_gate) {
  const int edges = span_gate ? errors.num_spanned_edges : errors.num_edges;
  return edges == 0 || errors.total_chi2 < chi2(residual_dim * edges);
}

std::vector<int> IntraClusterSurvivors(const std::vector<int>& cluster,
                                       const SubsetErrors& errors,
                                       int residual_dim,
                                       const ChiSquareQuantile& chi2,
                                       bool span_gate) {
  std::vector<int> survivors;
  if (!TotalErrorConsistent(errors, residual_dim, chi2, span_gate)) {
    return survivors;
  }
  for (size_t k = 0; k < cluster.size(); ++k) {
    if (errors.loop_chi2[k] < chi2(residual_dim)) {
      survivors.push_back(cluster[k]);
    }
  }
  return survivors;
}

std::vector<bool> InterClusterConsistent(
    const std::vector<std::vector<int>>& clusters, ConsistencySolver& solver,
    const ChiSquareQuantile& chi2, bool span_gate, int threads) {
  const int e = solver.residual_dim();
  const int n = static_cast<int>(clusters.size());
  std::vector<bool> good(n, false), rejected(n, false);
  std::vector<int> good_list;
  while (true) {
    // 1. Candidates: neither accepted nor rejected for now.
    std::vector<int> h;
    for (int c = 0; c < n; ++c) {
      if (!good[c] && !rejected[c]) h.push_back(c);
    }
    if (h.empty()) break;
    // 2. Keep the clusters with at least one link consistent with H jointly.
    std::vector<int> likely_set_asides;
    {
      const SubsetErrors errors = solver.Solve(LinksOf(clusters, h));
      std::vector<int> kept;
      std::vector<double> kept_ci;
      const std::vector<double> ci =
          ConsistencyIndices(errors.loop_chi2, 0, clusters, h, e, chi2);
      size_t offset = 0;
      for (size_t k = 0; k < h.size(); ++k) {
        const auto first = errors.loop_chi2.begin() + offset;
        const auto last = first + clusters[h[k]].size();
        if (std::any_of(first, last, [&](double d) { return d < chi2(e); })) {
          kept.push_back(h[k]);
          kept_ci.push_back(ci[k]);
        }
        offset += clusters[h[k]].size();
      }
      h.swap(kept);
      likely_set_asides = ByDecreasingIndex(h, kept_ci);
    }
    if (h.empty()) break;
    // 3. Joint test of good ∪ H, dropping the least consistent cluster of H
    // until it passes or H is empty.
    JointSolves joint(clusters, good_list, solver, threads);
    std::vector<int> set_aside;
    bool grew = false;
    while (!h.empty()) {
      const SubsetErrors& errors = joint.Get(h, likely_set_asides);
      const size_t num_links = errors.loop_chi2.size();
      const double links_chi2 = std::accumulate(errors.loop_chi2.begin(),
                                                errors.loop_chi2.end(), 0.0);
      if (TotalErrorConsistent(errors, e, chi2, span_gate) &&
          links_chi2 < chi2(e * static_cast<int>(num_links))) {
        for (const int c : h) good[c] = true;
        good_list.insert(good_list.end(), h.begin(), h.end());
        grew = true;
        break;
      }
      // CI of each cluster of H; its links follow good's in the solve.
      size_t offset = num_links;
      for (const int c : h) offset -= clusters[c].size();
      const std::vector<double> ci =
          ConsistencyIndices(errors.loop_chi2, offset, clusters, h, e, chi2);
      int worst = 0;
      double worst_ci = -1.0;
      for (size_t k = 0; k < h.size(); ++k) {
        if (ci[k] > worst_ci) {
          worst_ci = ci[k];
          worst = static_cast<int>(k);
        }
      }
      set_aside.push_back(h[worst]);
      h.erase(h.begin() + worst);
      likely_set_asides = ByDecreasingIndex(h, ci, worst);
    }
    // 4. New evidence gives rejected clusters another chance.
    if (grew) std::fill(rejected.begin(), rejected.end(), false);
    for (const int c : set_aside) rejected[c] = true;
  }
  return good;
}

}  // namespace rrr
