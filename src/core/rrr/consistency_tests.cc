#include "rrr/rrr/consistency_tests.h"

#include <algorithm>
#include <numeric>

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

}  // namespace

bool TotalErrorConsistent(const SubsetErrors& errors, int residual_dim,
                          const ChiSquareQuantile& chi2, bool span_gate) {
  const int edges = span_gate ? errors.num_spanned_edges : errors.num_edges;
  return edges == 0 || errors.total_chi2 < chi2(residual_dim * edges);
}

std::vector<int> IntraClusterConsistent(const std::vector<int>& cluster,
                                        ConsistencySolver& solver,
                                        const ChiSquareQuantile& chi2,
                                        bool span_gate) {
  return IntraClusterSurvivors(cluster, solver.Solve(cluster),
                               solver.residual_dim(), chi2, span_gate);
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
    const ChiSquareQuantile& chi2, bool span_gate) {
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
    {
      const SubsetErrors errors = solver.Solve(LinksOf(clusters, h));
      std::vector<int> kept;
      size_t offset = 0;
      for (const int c : h) {
        const auto first = errors.loop_chi2.begin() + offset;
        const auto last = first + clusters[c].size();
        if (std::any_of(first, last, [&](double d) { return d < chi2(e); })) {
          kept.push_back(c);
        }
        offset += clusters[c].size();
      }
      h.swap(kept);
    }
    if (h.empty()) break;
    // 3. Joint test of good ∪ H, dropping the least consistent cluster of H
    // until it passes or H is empty.
    std::vector<int> set_aside;
    bool grew = false;
    while (!h.empty()) {
      std::vector<int> joint = good_list;
      joint.insert(joint.end(), h.begin(), h.end());
      const std::vector<int> links = LinksOf(clusters, joint);
      const SubsetErrors errors = solver.Solve(links);
      const double links_chi2 = std::accumulate(errors.loop_chi2.begin(),
                                                errors.loop_chi2.end(), 0.0);
      if (TotalErrorConsistent(errors, e, chi2, span_gate) &&
          links_chi2 < chi2(e * static_cast<int>(links.size()))) {
        for (const int c : h) good[c] = true;
        good_list.insert(good_list.end(), h.begin(), h.end());
        grew = true;
        break;
      }
      // CI of each cluster of H; its links follow good's in `links`.
      size_t offset = links.size();
      for (const int c : h) offset -= clusters[c].size();
      int worst = 0;
      double worst_ci = -1.0;
      for (size_t k = 0; k < h.size(); ++k) {
        const auto& members = clusters[h[k]];
        const auto first = errors.loop_chi2.begin() + offset;
        const double ci = std::accumulate(first, first + members.size(), 0.0) /
                          chi2(e * static_cast<int>(members.size()));
        if (ci > worst_ci) {
          worst_ci = ci;
          worst = static_cast<int>(k);
        }
        offset += members.size();
      }
      set_aside.push_back(h[worst]);
      h.erase(h.begin() + worst);
    }
    // 4. New evidence gives rejected clusters another chance.
    if (grew) std::fill(rejected.begin(), rejected.end(), false);
    for (const int c : set_aside) rejected[c] = true;
  }
  return good;
}

}  // namespace rrr
