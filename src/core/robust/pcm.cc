#include "rrr/robust/pcm.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cstdint>
#include <numeric>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/graph/odometry_chain.h"
#include "rrr/rrr/chi_square.h"
#include "rrr/solver/pose_graph_solver.h"

namespace rrr {
namespace {

// A relative pose with the covariance of its right perturbation.
template <class Pose>
struct Uncertain {
  Pose pose;
  typename Constraint<Pose>::Information cov;

  Uncertain Inverse() const {
    const typename Pose::Jacobian ad = pose.Adjoint();
    return {pose.inverse(), ad * cov * ad.transpose()};
  }
  // this · other: x·Exp(ε₁)·y·Exp(ε₂) = xy·Exp(Ad(y⁻¹)ε₁ + ε₂).
  Uncertain operator*(const Uncertain& other) const {
    const typename Pose::Jacobian ad = other.pose.inverse().Adjoint();
    return {pose * other.pose, ad * cov * ad.transpose() + other.cov};
  }
};

// A loop from its earlier pose to its later one.
template <class Pose>
struct Link {
  int early, late;
  Uncertain<Pose> z;
};

// The condensed odometry from pose p to pose q (either order).
template <class Pose>
Uncertain<Pose> Odometry(const OdometryChain<Pose>& chain, int p, int q) {
  if (p == q) return {Pose(), Constraint<Pose>::Information::Zero()};
  if (p < q) return {chain.Relative(p, q), chain.CovarianceBetween(p, q)};
  return Odometry(chain, q, p).Inverse();
}

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

}  // namespace

template <class Pose>
Verdict VerifyWithPcm(const PoseGraph<Pose>& graph, const PcmOptions& options,
                      std::vector<Pose>* map, MinimizeResult* minimized) {
  const OdometryChain<Pose> chain = ChainOf(graph);
  const double gate = ChiSquareQuantile(options.probability)(Pose::kDof);
  std::vector<Link<Pose>> links;
  for (const auto& e : graph.loops()) {
    Uncertain<Pose> z{
        e.measurement,
        e.information.ldlt().solve(Constraint<Pose>::Information::Identity())};
    if (e.from < e.to) {
      links.push_back({e.from, e.to, z});
    } else {
      links.push_back({e.to, e.from, z.Inverse()});
    }
  }
  BitGraph consistent(links.size());
  for (size_t i = 0; i < links.size(); ++i) {
    for (size_t j = i + 1; j < links.size(); ++j) {
      const Link<Pose>& a = links[i];
      const Link<Pose>& b = links[j];
      // early_a -> late_a -> late_b -> early_b -> early_a: the identity.
      const Uncertain<Pose> cycle = a.z * Odometry(chain, a.late, b.late) *
                                    b.z.Inverse() *
                                    Odometry(chain, b.early, a.early);
      const typename Pose::Tangent r = cycle.pose.Log();
      const double d2 = r.dot(cycle.cov.ldlt().solve(r));
      if (d2 < gate) consistent.Connect(i, j);
    }
  }
  std::vector<bool> accepted(links.size(), false);
  for (const int k : GreedyClique(consistent, options.starts)) {
    accepted[k] = true;
  }
  Verdict verdict = VerdictOf(accepted);
  if (map) {
    const PoseGraphSolver<Pose> solver(graph, 1);
    *map = solver.Optimize(verdict.accepted, ConvergenceOptions(), minimized);
  }
  return verdict;
}

template Verdict VerifyWithPcm(const PoseGraph<Pose2>&, const PcmOptions&,
                               std::vector<Pose2>*, MinimizeResult*);
template Verdict VerifyWithPcm(const PoseGraph<Pose3>&, const PcmOptions&,
                               std::vector<Pose3>*, MinimizeResult*);

}  // namespace rrr
