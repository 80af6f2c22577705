// MapVerifier: the join rule, which relates the maps of odometry chains that
// loops between them may join (doc/rule.md, the join rule).
#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <numeric>
#include <utility>
#include <vector>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/rrr/map/map_verifier.h"
#include "rrr/solver/edge_error.h"

namespace rrr {
namespace {

// The frame in which map `moved`'s poses must be put (x ← frame · x) for
// `loops` between it and another map to fit best, both maps held as
// `estimate` has them: Gauss–Newton over the frame, from the frame that
// makes the first loop hold exactly, while the error decreases.
template <class Pose>
Pose Placement(const PoseGraph<Pose>& graph, const std::vector<int>& loops,
               const std::function<bool(int)>& in_moved,
               const std::function<Pose(int)>& estimate) {
  const auto moved = [&](int p, const Pose& frame) {
    return in_moved(p) ? frame * estimate(p) : estimate(p);
  };
  const auto error = [&](const Pose& frame) {
    double sum = 0.0;
    for (const int k : loops) {
      const Constraint<Pose>& e = graph.loops()[k];
      const typename Pose::Tangent r =
          EdgeResidual(e.measurement, moved(e.from, frame), moved(e.to, frame));
      sum += r.dot(e.information * r);
    }
    return sum;
  };
  const Constraint<Pose>& first = graph.loops()[loops.front()];
  Pose frame = in_moved(first.to)
                   ? estimate(first.from) * first.measurement *
                         estimate(first.to).inverse()
                   : estimate(first.to) * first.measurement.inverse() *
                         estimate(first.from).inverse();
  double chi2 = error(frame);
  const ConvergenceOptions convergence;
  for (int it = 0; it < convergence.max_iterations; ++it) {
    typename Pose::Jacobian h = Pose::Jacobian::Zero();
    typename Pose::Tangent g = Pose::Tangent::Zero();
    for (const int k : loops) {
      const Constraint<Pose>& e = graph.loops()[k];
      typename Pose::Jacobian ji, jj;
      const typename Pose::Tangent r = EdgeResidualAndJacobians(
          e.measurement, moved(e.from, frame), moved(e.to, frame), &ji, &jj);
      // A moved pose p goes as frame·Exp(δ)·p = frame·p·Exp(Ad(p⁻¹)δ).
      const bool to_moves = in_moved(e.to);
      const Pose& p = estimate(to_moves ? e.to : e.from);
      const typename Pose::Jacobian j =
          (to_moves ? jj : ji) * p.inverse().Adjoint();
      h += j.transpose() * e.information * j;
      g += j.transpose() * e.information * r;
    }
    const Pose next = frame * Pose::Exp(-h.ldlt().solve(g));
    const double next_chi2 = error(next);
    if (!(next_chi2 < chi2)) break;
    const bool small = chi2 - next_chi2 < convergence.relative_decrease * chi2;
    frame = next;
    chi2 = next_chi2;
    if (small) break;
  }
  return frame;
}

// The evidence of revisits of evidence `each` (exclusive hypotheses)
// together, in links: each passed check multiplies a revisit's odds by
// 1 / (1 − α) (a link that does not belong passes the gate of one that does
// no more often than one that does fails it), and exclusive hypotheses'
// odds add: log Σ (1/(1−α))^W / log(1/(1−α)), a soft maximum (0 for none).
double Together(const std::vector<int>& each, double alpha) {
  if (each.empty()) return 0.0;
  const double per_link = -std::log(1.0 - alpha);
  const int most = *std::max_element(each.begin(), each.end());
  double odds = 0.0;
  for (const int w : each) odds += std::exp(per_link * (w - most));
  return most + std::log(odds) / per_link;
}

}  // namespace

template <class Pose>
std::pair<int, int> MapVerifier<Pose>::ChainsOf(int c) const {
  const std::int64_t group = clustering_.clusters()[c].group;
  return {static_cast<int>(group >> 32), static_cast<int>(group & 0xffffffff)};
}

template <class Pose>
std::vector<int> MapVerifier<Pose>::OwnLinks(int c) const {
  std::vector<int> own;
  for (const int loop : clustering_.clusters()[c].loops) {
    switch (reasons_[loop].test) {
      case DecisionTest::kNotJudged:
      case DecisionTest::kAlone:
      case DecisionTest::kOwnLink:
      case DecisionTest::kOwn:
        break;
      default:
        own.push_back(loop);
    }
  }
  return own;
}

template <class Pose>
void MapVerifier<Pose>::Forget(int c) {
  for (auto it = agree_.begin(); it != agree_.end();) {
    const auto& [x, y] = it->first;
    it = std::count(x.begin(), x.end(), c) + std::count(y.begin(), y.end(), c)
             ? agree_.erase(it)
             : std::next(it);
  }
}

template <class Pose>
std::vector<int> MapVerifier<Pose>::Between(
    int a, int b, const std::function<bool(int)>& keep) const {
  std::vector<int> clusters;
  for (int c = 0; c < static_cast<int>(records_.size()); ++c) {
    const auto [x, y] = ChainsOf(c);
    if (std::minmax(x, y) == std::minmax(a, b) && keep(c)) {
      clusters.push_back(c);
    }
  }
  return clusters;
}

template <class Pose>
bool MapVerifier<Pose>::Adjacent(int a, int b) const {
  const Cluster& x = clustering_.clusters()[a];
  const Cluster& y = clustering_.clusters()[b];
  // Ranges closer than a window at both ends (as the clustering joins a
  // loop to a cluster): one revisit that the clustering cut.
  const auto near = [&](PoseId low1, PoseId high1, PoseId low2, PoseId high2) {
    return std::max(low1, low2) - std::min(high1, high2) <
           options_.cluster_window;
  };
  return x.group == y.group &&
         near(x.start_low, x.start_high, y.start_low, y.start_high) &&
         near(x.end_low, x.end_high, y.end_low, y.end_high);
}

template <class Pose>
std::vector<std::pair<int, std::vector<int>>> MapVerifier<Pose>::Revisits(
    const std::vector<int>& clusters) {
  // Union by the lower index (clusters ascend): each revisit under its first.
  std::vector<size_t> root(clusters.size());
  std::iota(root.begin(), root.end(), 0);
  const auto find = [&](size_t i) {
    while (root[i] != i) i = root[i];
    return i;
  };
  for (size_t i = 0; i < clusters.size(); ++i) {
    for (size_t j = i + 1; j < clusters.size(); ++j) {
      if (find(i) != find(j) && Adjacent(clusters[i], clusters[j]) &&
          Agree({clusters[i]}, {clusters[j]})) {
        root[find(j)] = find(i);
      }
    }
  }
  std::vector<std::pair<int, std::vector<int>>> revisits;
  std::vector<int> revisit_of(clusters.size(), -1);
  for (size_t i = 0; i < clusters.size(); ++i) {
    int& r = revisit_of[find(i)];
    if (r < 0) {
      r = static_cast<int>(revisits.size());
      revisits.emplace_back(-1, std::vector<int>());
    }
    revisits[r].first += static_cast<int>(OwnLinks(clusters[i]).size());
    revisits[r].second.push_back(clusters[i]);
  }
  std::stable_sort(
      revisits.begin(), revisits.end(),
      [](const auto& x, const auto& y) { return x.first > y.first; });
  return revisits;
}

template <class Pose>
bool MapVerifier<Pose>::Agree(const std::vector<int>& a,
                              const std::vector<int>& b) {
  const auto key = std::minmax(a, b);
  const auto known = agree_.find(key);
  if (known != agree_.end()) return known->second;
  std::vector<int> links;
  for (const std::vector<int>* set : {&a, &b}) {
    for (const int c : *set) {
      const std::vector<int> own = OwnLinks(c);
      links.insert(links.end(), own.begin(), own.end());
    }
  }
  const bool agree =
      Passes(Test(links, Against::kOdometry), Against::kOdometry);
  agree_.emplace(std::make_pair(key.first, key.second), agree);
  return agree;
}

template <class Pose>
typename MapVerifier<Pose>::Weighed MapVerifier<Pose>::Weigh(
    const std::vector<int>& clusters) {
  Weighed w;
  if (clusters.empty()) return w;
  const auto revisits = Revisits(clusters);
  w.evidence = revisits.front().first;
  w.revisit = revisits.front().second;
  std::vector<int> contradicting;
  for (size_t r = 1; r < revisits.size() &&
                     Together(contradicting, options_.alpha) < w.evidence;
       ++r) {
    if (revisits[r].first > 0 && !Agree(w.revisit, revisits[r].second)) {
      contradicting.push_back(revisits[r].first);
    }
  }
  w.against = Together(contradicting, options_.alpha);
  return w;
}

template <class Pose>
void MapVerifier<Pose>::Hold(int c, const std::vector<int>& links) {
  records_[c].status = Status::kHeld;
  records_[c].accepted.clear();
  const MapTrial own = Test(links, Against::kOdometry);
  Record(links, DecisionTest::kJoin, own.increase, own.free_frames);
  touched_.push_back(c);
}

template <class Pose>
void MapVerifier<Pose>::JudgeJoin(int a, int b) {
  if (map_->MapOf(a) == map_->MapOf(b)) return;
  const Weighed weighed = Weigh(Between(
      a, b, [&](int c) { return records_[c].status == Status::kHeld; }));
  if (weighed.Joins()) Join(weighed.revisit);
}

template <class Pose>
void MapVerifier<Pose>::Join(const std::vector<int>& revisit) {
  ++stats_.joins;
  const ChainOdometry<Pose>& chains = this->chains();
  const auto [a, b] = ChainsOf(revisit.front());
  const int moved = std::max(map_->MapOf(a), map_->MapOf(b));
  std::vector<int> links;
  for (const int c : revisit) {
    const std::vector<int> own = OwnLinks(c);
    links.insert(links.end(), own.begin(), own.end());
  }
  map_->Move(moved, Placement<Pose>(
                        this->graph(), links,
                        [&](int p) {
                          return map_->MapOf(chains.chain_of(p)) == moved;
                        },
                        [&](int p) { return map_->Estimate(p); }));
  // The revisit's clusters, the largest first, then every cluster held
  // between maps that are one now.
  std::vector<int> order = revisit;
  std::stable_sort(order.begin(), order.end(), [&](int x, int y) {
    return OwnLinks(x).size() > OwnLinks(y).size();
  });
  const auto judge = [&](int c) {
    records_[c].status = Status::kRefused;
    JudgeAgainstMap(c, OwnLinks(c));
  };
  for (const int c : order) judge(c);
  for (int c = 0; c < static_cast<int>(records_.size()); ++c) {
    const auto [x, y] = ChainsOf(c);
    if (records_[c].status == Status::kHeld &&
        map_->MapOf(x) == map_->MapOf(y)) {
      judge(c);
    }
  }
  arbiter_due_ = true;
}

template <class Pose>
void MapVerifier<Pose>::ReviseJoin(int c) {
  const auto [a, b] = ChainsOf(c);
  if (a == b || map_->MapOf(a) != map_->MapOf(b) ||
      map_->MapOfWithout(a, a, b) == map_->MapOfWithout(b, a, b) ||
      OwnLinks(c).empty()) {
    return;
  }
  // The join weighed again with its rivals, the clusters refused against
  // the map it made (JudgeJoin's weighing, as if they were apart): it stands
  // while the strongest revisit is one it holds, or agrees with those it
  // holds, and has more evidence than those that contradict it.
  const std::vector<int> between = Between(a, b, [&](int r) {
    return records_[r].status == Status::kAccepted ||
           (records_[r].status == Status::kRefused && !OwnLinks(r).empty());
  });
  const std::vector<int> joined = Between(
      a, b, [&](int r) { return records_[r].status == Status::kAccepted; });
  const Weighed weighed = Weigh(between);
  const bool strongest_holds =
      std::any_of(
          weighed.revisit.begin(), weighed.revisit.end(),
          [&](int r) { return records_[r].status == Status::kAccepted; }) ||
      Agree(weighed.revisit, joined);
  if (weighed.Joins() && strongest_holds) return;
  ++stats_.join_revisions;
  // Apart again, every cluster between them waits for the join rule.
  for (const int r : joined) LeaveMap(r);
  for (const int r : between) Hold(r, OwnLinks(r));
  JudgeJoin(a, b);
}

template <class Pose>
void MapVerifier<Pose>::RefuseApart() {
  std::map<std::pair<int, int>, std::vector<int>> held;  // by pair of chains
  for (size_t c = 0; c < records_.size(); ++c) {
    if (records_[c].status != Status::kHeld) continue;
    const auto [x, y] = ChainsOf(static_cast<int>(c));
    held[std::minmax(x, y)].push_back(static_cast<int>(c));
  }
  for (const auto& [pair, clusters] : held) {
    const auto revisits = Revisits(clusters);
    std::vector<int> every;
    for (const auto& [evidence, revisit] : revisits) {
      if (evidence > 0) every.push_back(evidence);
    }
    const double together = std::max(Together(every, options_.alpha), 1.0);
    for (const auto& [evidence, revisit] : revisits) {
      for (const int c : revisit) {
        const std::vector<int> links = OwnLinks(c);
        Record(links, DecisionTest::kApart, evidence);
        for (const int loop : links) reasons_[loop].gate = together;
        records_[c].status = Status::kRefused;
        touched_.push_back(c);
      }
    }
  }
}

// The members the other parts of MapVerifier call.
#define RRR_INSTANTIATE_JOIN(Pose)                                     \
  template std::pair<int, int> MapVerifier<Pose>::ChainsOf(int) const; \
  template void MapVerifier<Pose>::Forget(int);                        \
  template void MapVerifier<Pose>::Hold(int, const std::vector<int>&); \
  template void MapVerifier<Pose>::JudgeJoin(int, int);                \
  template void MapVerifier<Pose>::ReviseJoin(int);                    \
  template void MapVerifier<Pose>::RefuseApart();
RRR_INSTANTIATE_JOIN(Pose2)
RRR_INSTANTIATE_JOIN(Pose3)
#undef RRR_INSTANTIATE_JOIN

}  // namespace rrr
