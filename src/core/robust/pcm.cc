#include "rrr/robust/pcm.h"

#include <algorithm>
#include <cstdint>
#include <map>
#include <numeric>
#include <utility>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/graph/chain_spans.h"
#include "rrr/graph/odometry_chain.h"
#include "rrr/graph/uncertain_pose.h"
#include "rrr/rrr/chi_square.h"

namespace rrr {
namespace {

// Rows of a symmetric bit matrix.
class BitGraph {
 public:
  explicit BitGraph(size_t n)
      : n_(n), words_((n + 63) / 64), bits_(n * words_) {}
  void Connect(size_t a, size_t b) {
    bits_[a * words_ + b / 64] |= uint64_t{1} << (b % 64);
    bits_[b * words_ + a / 64] |= uint64_t{1} << (a % 64);
  }
  bool Connected(size_t a, size_t b) const {
    return (bits_[a * words_ + b / 64] >> (b % 64)) & 1;
  }
  size_t size() const { return n_; }

 private:
  size_t n_, words_;
  std::vector<uint64_t> bits_;
};

// A large clique: from each of the `starts` vertices of highest degree, add
// the candidate of highest degree while one is adjacent to all chosen.
std::vector<int> GreedyClique(const BitGraph& g, int starts) {
  const size_t n = g.size();
  std::vector<int> degree(n, 0);
  for (size_t a = 0; a < n; ++a)
    for (size_t b = 0; b < n; ++b) degree[a] += g.Connected(a, b);
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return degree[a] > degree[b]; });
  std::vector<int> best;
  for (int s = 0; s < std::min<int>(starts, static_cast<int>(n)); ++s) {
    const int v = order[s];
    if (degree[v] + 1 <= static_cast<int>(best.size())) break;
    std::vector<int> clique{v}, candidates;
    for (const int u : order) {
      if (u != v && g.Connected(v, u) &&
          degree[u] + 1 > static_cast<int>(best.size())) {
        candidates.push_back(u);
      }
    }
    // `candidates` stays in decreasing degree: take the first, filter.
    while (!candidates.empty()) {
      const int u = candidates.front();
      clique.push_back(u);
      std::vector<int> next;
      for (size_t k = 1; k < candidates.size(); ++k) {
        if (g.Connected(u, candidates[k])) next.push_back(candidates[k]);
      }
      candidates.swap(next);
    }
    if (clique.size() > best.size()) best = clique;
  }
  return best;
}

// A loop from its pose on the lower chain (the earlier pose, on one chain)
// to its pose on the other.
template <class Pose>
struct Link {
  int early, late;
  UncertainPose<Pose> z;
};

}  // namespace

template <class Pose>
Verdict VerifyWithPcm(const PoseGraph<Pose>& graph, const PcmOptions& options,
                      ChainMaps<Pose>* maps) {
  const std::vector<ChainSpan> spans = ChainSpansOf(graph);
  const std::vector<OdometryChain<Pose>> chains = OdometryOf(graph, spans);
  // The condensed odometry from pose p to pose q of chain c (either order).
  const auto odometry = [&](int c, int p, int q) {
    return OdometryBetween(chains[c], p - spans[c].first, q - spans[c].first);
  };
  const double gate = ChiSquareQuantile(options.probability)(Pose::kDof);
  // The loops grouped by the pair of chains they join (a chain with itself
  // for the loops inside it).
  std::map<std::pair<int, int>, std::vector<int>> groups;
  std::vector<Link<Pose>> links;
  for (size_t k = 0; k < graph.loops().size(); ++k) {
    const auto& e = graph.loops()[k];
    const UncertainPose<Pose> z = MeasurementOf(e);
    if (e.from < e.to) {
      links.push_back({e.from, e.to, z});
    } else {
      links.push_back({e.to, e.from, z.Inverse()});
    }
    groups[{ChainHolding(spans, links.back().early),
            ChainHolding(spans, links.back().late)}]
        .push_back(static_cast<int>(k));
  }
  std::vector<bool> accepted(links.size(), false);
  for (const auto& [chain_pair, members] : groups) {
    const auto [ca, cb] = chain_pair;
    BitGraph consistent(members.size());
    for (size_t i = 0; i < members.size(); ++i) {
      for (size_t j = i + 1; j < members.size(); ++j) {
        const Link<Pose>& a = links[members[i]];
        const Link<Pose>& b = links[members[j]];
        // early_a -> late_a -> late_b -> early_b -> early_a: the identity.
        const UncertainPose<Pose> cycle = a.z * odometry(cb, a.late, b.late) *
                                          b.z.Inverse() *
                                          odometry(ca, b.early, a.early);
        if (cycle.SquaredDistance() < gate) consistent.Connect(i, j);
      }
    }
    for (const int k : GreedyClique(consistent, options.starts)) {
      accepted[members[k]] = true;
    }
  }
  Verdict verdict = VerdictOf(accepted);
  if (maps) {
    *maps = ChainMaps<Pose>();
    maps->chains = spans;
    maps->estimates = graph.estimates();
    for (const auto& [chain_pair, members] : groups) {
      if (chain_pair.first == chain_pair.second) continue;
      ChainPair<Pose> pair;
      pair.first = chain_pair.first;
      pair.second = chain_pair.second;
      pair.candidates = members;
      for (const int k : members) {
        if (accepted[k]) pair.accepted.push_back(k);
      }
      pair.joined = !pair.accepted.empty();
      if (pair.joined) {
        // Placed by its first accepted loop: x_a · z = relative · x_b.
        const Link<Pose>& l = links[pair.accepted.front()];
        const auto& x = graph.estimates();
        pair.relative = x[l.early] * l.z.pose * x[l.late].inverse();
      }
      maps->pairs.push_back(std::move(pair));
    }
    MinimizeMaps(graph, verdict.accepted, maps);
  }
  return verdict;
}

template Verdict VerifyWithPcm(const PoseGraph<Pose2>&, const PcmOptions&,
                               ChainMaps<Pose2>*);
template Verdict VerifyWithPcm(const PoseGraph<Pose3>&, const PcmOptions&,
                               ChainMaps<Pose3>*);

}  // namespace rrr
