// A first-order lower bound of what a loop between odometry chains brings
// to a map that holds them, from paths of measurements between its ends.
#ifndef RRR_CORE_RRR_CHAINS_PATH_BOUND_H_
#define RRR_CORE_RRR_CHAINS_PATH_BOUND_H_

#include <algorithm>
#include <cstdlib>
#include <limits>
#include <tuple>
#include <utility>
#include <vector>

#include "rrr/graph/chain_spans.h"
#include "rrr/graph/odometry_chain.h"
#include "rrr/graph/pose_graph.h"
#include "rrr/graph/uncertain_pose.h"

namespace rrr {

// Over a graph of whole chains laid end to end. A loop brings to a map, at
// the map's minimum x, to first order, its squared Mahalanobis error at x
// with the covariance of the map's relative pose of its ends; the map holds
// any one path of measurements between the ends and more, so that path's
// covariance bounds the map's from above and the loop's error with it
// bounds what the loop brings from below. Several loops together bring at
// least what each brings alone.
template <class Pose>
class PathBound {
 public:
  // `graph` holds the chains `spans` (of a larger graph) in that order, with
  // `odometry` each one's condensed odometry (OdometryOf); `graph` must
  // outlive this.
  PathBound(const PoseGraph<Pose>& graph, const std::vector<ChainSpan>& spans,
            std::vector<OdometryChain<Pose>> odometry)
      : graph_(graph),
        offsets_(Offsets(spans)),
        odometry_(std::move(odometry)) {}

  // Whether poses `p` and `q` of the graph are on one chain.
  bool SameChain(int p, int q) const { return SpanAt(p) == SpanAt(q); }

  // The largest bound over the loops `loops` (of the graph) and the paths
  // through the loops `hops` (of the graph, between chains) at the map's
  // minimum, whose pose p is `estimate(p)` (asked for the loops' ends only):
  // odometry, and the hops (PathsBetween). 0 while no path leads.
  template <class Estimate>
  double Least(const std::vector<int>& loops, const std::vector<int>& hops,
               const Estimate& estimate) const {
    double least = 0.0;
    for (const int k : loops) {
      const auto& e = graph_.loops()[k];
      const Pose relative = estimate(e.from).between(estimate(e.to));
      for (const UncertainPose<Pose>& path : PathsBetween(e.from, e.to, hops)) {
        const UncertainPose<Pose> map{relative, path.cov};
        least = std::max(least,
                         (map.Inverse() * MeasurementOf(e)).SquaredDistance());
      }
    }
    return least;
  }

 private:
  static std::vector<int> Offsets(const std::vector<ChainSpan>& spans) {
    std::vector<int> offsets;
    int next = 0;
    for (const ChainSpan& span : spans) {
      offsets.push_back(next);
      next += span.size();
    }
    return offsets;
  }

  // The chain (index into offsets_) of pose `p` of the graph.
  int SpanAt(int p) const {
    return static_cast<int>(
        std::upper_bound(offsets_.begin(), offsets_.end(), p) -
        offsets_.begin() - 1);
  }

  // The odometry of chain `s` from its pose `p` to its pose `q` (poses of
  // graph_).
  UncertainPose<Pose> Odometry(int s, int p, int q) const {
    return OdometryBetween(odometry_[s], p - offsets_[s], q - offsets_[s]);
  }

  // Paths of measurements from pose `p` to pose `q` of graph_
  // through the loops `hops` (loops of graph_ between chains), over the
  // fewest chains: into the last chain, one path through each hop that
  // enters it; before, each chain left by the hop nearest (in poses) to
  // where the path entered it. None if no hops lead from p's chain to q's.
  std::vector<UncertainPose<Pose>> PathsBetween(
      int p, int q, const std::vector<int>& hops) const {
    const int from = SpanAt(p), to = SpanAt(q);
    std::vector<int> parent(offsets_.size(), -1);
    parent[from] = from;
    std::vector<int> queue{from};
    for (size_t n = 0; n < queue.size() && parent[to] < 0; ++n) {
      for (const int k : hops) {
        const auto& e = graph_.loops()[k];
        for (const auto& [u, v] : {std::pair(SpanAt(e.from), SpanAt(e.to)),
                                   std::pair(SpanAt(e.to), SpanAt(e.from))}) {
          if (u == queue[n] && parent[v] < 0) {
            parent[v] = u;
            queue.push_back(v);
          }
        }
      }
    }
    if (parent[to] < 0) return {};
    std::vector<int> chains{to};
    while (chains.back() != from) chains.push_back(parent[chains.back()]);
    std::reverse(chains.begin(), chains.end());
    // The hops from chain u to chain v: (its pose on u, on v, measurement).
    const auto hops_between = [&](int u, int v) {
      std::vector<std::tuple<int, int, UncertainPose<Pose>>> out;
      for (const int k : hops) {
        const auto& e = graph_.loops()[k];
        if (SpanAt(e.from) == u && SpanAt(e.to) == v) {
          out.emplace_back(e.from, e.to, MeasurementOf(e));
        } else if (SpanAt(e.to) == u && SpanAt(e.from) == v) {
          out.emplace_back(e.to, e.from, MeasurementOf(e).Inverse());
        }
      }
      return out;
    };
    UncertainPose<Pose> path;
    int at = p;
    for (size_t n = 0; n + 2 < chains.size(); ++n) {
      const auto next = hops_between(chains[n], chains[n + 1]);
      const auto nearest = std::min_element(
          next.begin(), next.end(), [at](const auto& x, const auto& y) {
            return std::abs(std::get<0>(x) - at) <
                   std::abs(std::get<0>(y) - at);
          });
      path = path * Odometry(chains[n], at, std::get<0>(*nearest)) *
             std::get<2>(*nearest);
      at = std::get<1>(*nearest);
    }
    const int last = chains[chains.size() - 2];
    std::vector<UncertainPose<Pose>> paths;
    for (const auto& [leave, enter, z] : hops_between(last, to)) {
      paths.push_back(path * Odometry(last, at, leave) * z *
                      Odometry(to, enter, q));
    }
    return paths;
  }

  const PoseGraph<Pose>& graph_;
  const std::vector<int> offsets_;  // each chain's first pose in the graph
  const std::vector<OdometryChain<Pose>> odometry_;  // each chain's
};

}  // namespace rrr

#endif  // RRR_CORE_RRR_CHAINS_PATH_BOUND_H_
