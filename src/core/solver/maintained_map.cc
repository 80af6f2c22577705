#include "rrr/solver/maintained_map.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <utility>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/solver/edge_error.h"
#include "rrr/solver/solve_in_parallel.h"

namespace rrr {
namespace {

// The pose x minimizing the error of edges a -> x and x -> b with x_a and
// x_b held, from `x` on (Gauss–Newton on one pose).
template <class Pose>
Pose BestBetween(const Constraint<Pose>& from_a, const Pose& xa,
                 const Constraint<Pose>& to_b, const Pose& xb, Pose x) {
  constexpr int D = Pose::kDof;
  for (int it = 0; it < 8; ++it) {
    typename Pose::Jacobian ja, jx, jx2, jb;
    const typename Pose::Tangent ra =
        EdgeResidualAndJacobians(from_a.measurement, xa, x, &ja, &jx);
    const typename Pose::Tangent rb =
        EdgeResidualAndJacobians(to_b.measurement, x, xb, &jx2, &jb);
    const Eigen::Matrix<double, D, D> h =
        jx.transpose() * from_a.information * jx +
        jx2.transpose() * to_b.information * jx2;
    const typename Pose::Tangent g = jx.transpose() * from_a.information * ra +
                                     jx2.transpose() * to_b.information * rb;
    const typename Pose::Tangent step = h.ldlt().solve(-g);
    if (!step.allFinite()) break;
    x = x * Pose::Exp(step);
    if (step.squaredNorm() < 1e-20) break;
  }
  return x;
}

}  // namespace

template <class Pose>
MaintainedMap<Pose>::MaintainedMap(const PoseGraph<Pose>& graph,
                                   const ChainOdometry<Pose>& chains,
                                   const ConvergenceOptions& convergence,
                                   int most_junctions)
    : graph_(graph),
      chains_(chains),
      convergence_(convergence),
      most_junctions_(most_junctions) {
  for (int c = 0; c < chains.num_chains(); ++c) AddChain(c);
}

template <class Pose>
void MaintainedMap<Pose>::AddChain(int chain) {
  if (chain != static_cast<int>(map_of_.size())) {
    throw std::logic_error("chains are taken in in order");
  }
  const int first = chains_.poses(chain).front();
  Junction& j = junctions_[chains_.Key(first)];
  j.pose = first;
  j.x = graph_.estimates().at(first);
  map_of_.push_back(chain);
}

template <class Pose>
std::vector<int> MaintainedMap<Pose>::Maps(int a, int b) const {
  // Union by the lower chain over the pairs with loops (few, as chains are).
  std::vector<int> map(map_of_.size());
  for (size_t c = 0; c < map.size(); ++c) map[c] = static_cast<int>(c);
  const auto root = [&](int c) {
    while (map[c] != c) c = map[c];
    return c;
  };
  for (const auto& [pair, count] : between_) {
    if (count == 0 || (pair.first == a && pair.second == b)) continue;
    const int x = root(pair.first), y = root(pair.second);
    if (x != y) map[std::max(x, y)] = std::min(x, y);
  }
  for (size_t c = 0; c < map.size(); ++c) map[c] = root(static_cast<int>(c));
  return map;
}

template <class Pose>
int MaintainedMap<Pose>::MapOfWithout(int chain, int a, int b) const {
  return Maps(std::min(a, b), std::max(a, b))[chain];
}

template <class Pose>
bool MaintainedMap<Pose>::Held(int pose) const {
  const int c = chains_.chain_of(pose);
  return chains_.position(pose) == 0 && map_of_[c] == c;
}

template <class Pose>
bool MaintainedMap<Pose>::Contains(int loop) const {
  return loop < static_cast<int>(in_map_.size()) && in_map_[loop];
}

template <class Pose>
double MaintainedMap<Pose>::LoopChi2(int loop) const {
  const auto& e = graph_.loops()[loop];
  const typename Pose::Tangent r =
      EdgeResidual(e.measurement, Estimate(e.from), Estimate(e.to));
  return r.dot(e.information * r);
}

template <class Pose>
Pose MaintainedMap<Pose>::Estimate(int pose) const {
  const Key key = chains_.Key(pose);
  auto next = junctions_.upper_bound(key);
  auto prev = std::prev(next);  // the chain's first pose is a junction
  if (prev->first == key) return prev->second.x;
  const Constraint<Pose> from_prev = chains_.Between(prev->second.pose, pose);
  Pose forward = prev->second.x * from_prev.measurement;
  if (next == junctions_.end() || !SameChain(key, next->first)) {
    return forward;
  }
  return BestBetween(from_prev, prev->second.x,
                     chains_.Between(pose, next->second.pose), next->second.x,
                     forward);
}

template <class Pose>
std::vector<Pose> MaintainedMap<Pose>::Estimates(int threads) const {
  const std::int64_t n = graph_.num_poses();
  std::vector<Pose> x(n);
  // Contiguous ranges of poses, a few per thread; each estimate is its own.
  const int workers = std::max(threads, 1);
  const std::int64_t ranges = std::min<std::int64_t>(n, 4LL * workers);
  ForEachInParallel(ranges, workers, [&](size_t r) {
    const std::int64_t range = static_cast<std::int64_t>(r);
    for (std::int64_t p = n * range / ranges; p < n * (range + 1) / ranges;
         ++p) {
      x[p] = Estimate(static_cast<int>(p));
    }
  });
  return x;
}

template <class Pose>
void MaintainedMap<Pose>::Insert(int pose, bool temporary) {
  const Key key = chains_.Key(pose);
  auto it = junctions_.find(key);
  if (it == junctions_.end()) {
    Junction j;
    j.pose = pose;
    j.x = Estimate(pose);
    it = junctions_.emplace(key, std::move(j)).first;
  }
  if (temporary) ++it->second.temporary;
}

template <class Pose>
void MaintainedMap<Pose>::Release(int pose) {
  const auto it = junctions_.find(chains_.Key(pose));
  if (it == junctions_.end() || chains_.position(pose) == 0) return;
  if (it->second.temporary > 0) --it->second.temporary;
  if (it->second.temporary == 0 && it->second.loops.empty()) {
    junctions_.erase(it);
  }
}

template <class Pose>
std::vector<int> MaintainedMap<Pose>::Region(const std::vector<int>& seeds,
                                             int radius) const {
  if (reached_.size() < static_cast<size_t>(graph_.num_poses())) {
    reached_.resize(graph_.num_poses(), false);
  }
  std::vector<Key> region;
  const auto visit = [&](int pose, std::vector<int>* frontier) {
    if (reached_[pose]) return;
    reached_[pose] = true;
    region.push_back(chains_.Key(pose));
    frontier->push_back(pose);
  };
  std::vector<int> frontier, next_frontier;
  for (const int s : seeds) visit(s, &frontier);
  for (int h = 1; h <= radius && !frontier.empty() &&
                  region.size() < static_cast<size_t>(most_junctions_);
       ++h) {
    next_frontier.clear();
    for (const int p : frontier) {
      const auto it = junctions_.find(chains_.Key(p));
      if (it != junctions_.begin() &&
          SameChain(std::prev(it)->first, it->first)) {
        visit(std::prev(it)->second.pose, &next_frontier);
      }
      if (std::next(it) != junctions_.end() &&
          SameChain(it->first, std::next(it)->first)) {
        visit(std::next(it)->second.pose, &next_frontier);
      }
      for (const int k : it->second.loops) {
        const auto& e = graph_.loops()[k];
        visit(e.from == p ? e.to : e.from, &next_frontier);
      }
    }
    frontier.swap(next_frontier);
  }
  std::sort(region.begin(), region.end());
  std::vector<int> poses(region.size());
  for (size_t k = 0; k < region.size(); ++k) {
    poses[k] = chains_.PoseOfKey(region[k]);
    reached_[poses[k]] = false;
  }
  return poses;
}

template <class Pose>
const Constraint<Pose>& MaintainedMap<Pose>::ToNext(
    typename Junctions::iterator it) {
  const int next = std::next(it)->second.pose;
  Junction& j = it->second;
  if (j.next != next) {
    j.to_next = chains_.Between(j.pose, next);
    j.next = next;
  }
  return j.to_next;
}

template <class Pose>
MapTrial MaintainedMap<Pose>::Minimize(const std::vector<int>& region,
                                       const std::vector<int>& extra,
                                       std::vector<Pose>* relaxed,
                                       double fails_above) {
  // Local indices: the region first (in key order), then the junctions it
  // borders in the order the edges reach them (local_, cleared on return).
  std::vector<typename Junctions::iterator> at(region.size());
  for (size_t k = 0; k < region.size(); ++k) {
    const auto next = k > 0 ? std::next(at[k - 1]) : junctions_.end();
    at[k] = next != junctions_.end() && next->second.pose == region[k]
                ? next
                : junctions_.find(chains_.Key(region[k]));
  }
  if (local_.size() < static_cast<size_t>(graph_.num_poses())) {
    local_.resize(graph_.num_poses(), -1);
  }
  std::vector<int> poses = region;
  const struct Clear {
    std::vector<int>* local;
    const std::vector<int>* poses;
    ~Clear() {
      for (const int p : *poses) (*local)[p] = -1;
    }
  } clear{&local_, &poses};
  for (size_t k = 0; k < region.size(); ++k) {
    local_[region[k]] = static_cast<int>(k);
  }
  const auto index = [&](int pose) {
    int& local = local_[pose];
    if (local < 0) {
      local = static_cast<int>(poses.size());
      poses.push_back(pose);
    }
    return local;
  };
  std::vector<Constraint<Pose>> edges;
  std::vector<int> map_loops;
  for (size_t k = 0; k < region.size(); ++k) {
    const int p = region[k];
    const auto it = at[k];
    const auto next = std::next(it);
    if (next != junctions_.end() && SameChain(it->first, next->first)) {
      Constraint<Pose> e = ToNext(it);
      e.from = index(p);
      e.to = index(next->second.pose);
      edges.push_back(e);
    }
    if (it != junctions_.begin() &&
        SameChain(std::prev(it)->first, it->first)) {
      const auto before = std::prev(it);
      const int local = local_[before->second.pose];
      if (local < 0 || local >= static_cast<int>(region.size())) {
        Constraint<Pose> e = ToNext(before);
        e.from = index(before->second.pose);
        e.to = index(p);
        edges.push_back(e);
      }
    }
    map_loops.insert(map_loops.end(), it->second.loops.begin(),
                     it->second.loops.end());
  }
  std::sort(map_loops.begin(), map_loops.end());
  map_loops.erase(std::unique(map_loops.begin(), map_loops.end()),
                  map_loops.end());
  const size_t num_chain_and_map = edges.size() + map_loops.size();
  for (const int k : map_loops) edges.push_back(graph_.loops()[k]);
  for (const int k : extra) edges.push_back(graph_.loops()[k]);
  for (size_t k = num_chain_and_map - map_loops.size(); k < edges.size(); ++k) {
    edges[k].from = index(edges[k].from);
    edges[k].to = index(edges[k].to);
  }

  std::vector<Pose> x(poses.size());
  for (size_t k = 0; k < region.size(); ++k) x[k] = at[k]->second.x;
  for (size_t k = region.size(); k < poses.size(); ++k) {
    x[k] = junctions_.at(chains_.Key(poses[k])).x;
  }
  std::vector<int> free;
  for (size_t k = 0; k < region.size(); ++k) {
    if (!Held(region[k])) free.push_back(static_cast<int>(k));
  }
  std::vector<const Constraint<Pose>*> pointers;
  pointers.reserve(edges.size());
  for (const Constraint<Pose>& e : edges) pointers.push_back(&e);
  // One analysis serves both minimizations: without `extra` (weight 0, the
  // same system as without their edges) and with them.
  LocalProblem<Pose> problem(static_cast<int>(x.size()), free, pointers);
  if (relaxed) {
    std::vector<double> weights(edges.size(), 1.0);
    std::fill(weights.begin() + num_chain_and_map, weights.end(), 0.0);
    problem.SetWeights(std::move(weights));
    problem.Minimize(&x, convergence_);
    relaxed->clear();
    for (size_t k = 0; k < region.size(); ++k) relaxed->push_back(x[k]);
    problem.SetWeights(std::vector<double>(edges.size(), 1.0));
  }
  double before = 0.0;
  std::vector<double> chi2_before(num_chain_and_map);
  for (size_t k = 0; k < num_chain_and_map; ++k) {
    chi2_before[k] = EdgeChi2(edges[k], x);
    before += chi2_before[k];
  }

  MapTrial trial;
  trial.minimize = problem.Minimize(&x, convergence_, before + fails_above);
  trial.num_free = static_cast<int>(free.size());
  trial.increase = trial.minimize.final_chi2 - before;
  for (size_t k = num_chain_and_map; k < edges.size(); ++k) {
    trial.loop_chi2.push_back(EdgeChi2(edges[k], x));
  }
  for (size_t k = 0; k < map_loops.size(); ++k) {
    const size_t edge = num_chain_and_map - map_loops.size() + k;
    trial.map_loops.push_back(
        {map_loops[k], chi2_before[edge], EdgeChi2(edges[edge], x)});
  }
  for (const int k : free) at[k]->second.x = x[k];
  return trial;
}

template <class Pose>
MapTrial MaintainedMap<Pose>::Try(const std::vector<int>& loops, int radius,
                                  double fails_above) {
  last_trial_.reset();
  const std::vector<int> ends = PosesTouched(graph_, loops);
  for (const int p : ends) Insert(p, true);
  const std::vector<int> region = Region(ends, radius);
  std::vector<Pose> relaxed;
  MapTrial trial = Minimize(region, loops, &relaxed, fails_above);
  auto kept = std::make_unique<KeptTrial>();
  kept->loops = loops;
  kept->radius = radius;
  for (size_t k = 0; k < region.size(); ++k) {
    Junction& j = junctions_.at(chains_.Key(region[k]));
    kept->estimate.emplace_back(region[k], j.x);
    j.x = relaxed[k];
  }
  for (const int p : ends) Release(p);
  last_trial_ = std::move(kept);
  return trial;
}

template <class Pose>
MapTrial MaintainedMap<Pose>::Widen(
    MapTrial trial, const std::vector<int>& loops, int radius, double gate,
    double significant, const std::function<bool(const MapTrial&)>& passes,
    int* tries) {
  for (int r = 2 * radius; trial.minimize.solved && !passes(trial); r *= 2) {
    MapTrial wider = Try(loops, r, gate);
    ++*tries;
    if (wider.num_free == trial.num_free) break;  // the whole region
    const double lowered = trial.increase - wider.increase;
    trial = std::move(wider);
    if (lowered <= significant) break;
  }
  return trial;
}

template <class Pose>
void MaintainedMap<Pose>::KeepTrial(double significant) {
  if (!last_trial_) throw std::logic_error("no trial to keep");
  const std::unique_ptr<KeptTrial> trial = std::move(last_trial_);
  for (const int p : PosesTouched(graph_, trial->loops)) Insert(p, false);
  Attach(trial->loops);
  for (const auto& [pose, x] : trial->estimate) {
    junctions_.at(chains_.Key(pose)).x = x;
  }
  Relax(trial->loops, 2 * trial->radius, significant);
}

template <class Pose>
void MaintainedMap<Pose>::Relax(const std::vector<int>& loops, int radius,
                                double significant) {
  last_trial_.reset();
  const std::vector<int> ends = PosesTouched(graph_, loops);
  size_t size = 0;
  for (int r = radius;; r *= 2) {
    const std::vector<int> region = Region(ends, r);
    if (region.size() == size) return;  // the whole connected map
    size = region.size();
    const MinimizeResult result = Minimize(region, {}).minimize;
    if (!(result.initial_chi2 - result.final_chi2 > significant)) return;
  }
}

template <class Pose>
void MaintainedMap<Pose>::Attach(const std::vector<int>& loops) {
  if (in_map_.size() < graph_.loops().size()) {
    in_map_.resize(graph_.loops().size(), false);
  }
  bool between = false;
  for (const int k : loops) {
    if (in_map_[k]) continue;
    in_map_[k] = true;
    ++num_loops_;
    const auto& e = graph_.loops()[k];
    junctions_.at(chains_.Key(e.from)).loops.push_back(k);
    junctions_.at(chains_.Key(e.to)).loops.push_back(k);
    const int a = chains_.chain_of(e.from), b = chains_.chain_of(e.to);
    if (a != b) {
      ++between_[{std::min(a, b), std::max(a, b)}];
      between = true;
    }
  }
  if (between) map_of_ = Maps(-1, -1);
}

template <class Pose>
void MaintainedMap<Pose>::Detach(const std::vector<int>& loops) {
  bool between = false;
  for (const int k : loops) {
    if (!Contains(k)) continue;
    in_map_[k] = false;
    --num_loops_;
    const auto& e = graph_.loops()[k];
    for (const int p : {e.from, e.to}) {
      auto& list = junctions_.at(chains_.Key(p)).loops;
      list.erase(std::find(list.begin(), list.end(), k));
    }
    const int a = chains_.chain_of(e.from), b = chains_.chain_of(e.to);
    if (a != b) {
      const auto pair = std::make_pair(std::min(a, b), std::max(a, b));
      if (--between_[pair] == 0) between_.erase(pair);
      between = true;
    }
  }
  if (between) map_of_ = Maps(-1, -1);
}

template <class Pose>
void MaintainedMap<Pose>::Add(const std::vector<int>& loops, int radius,
                              double significant) {
  for (const int p : PosesTouched(graph_, loops)) Insert(p, false);
  Attach(loops);
  Relax(loops, radius, significant);
}

template <class Pose>
void MaintainedMap<Pose>::Remove(const std::vector<int>& loops, int radius,
                                 double significant) {
  const std::vector<int> ends = PosesTouched(graph_, loops);
  Detach(loops);
  Relax(loops, radius, significant);
  for (const int p : ends) Release(p);
}

template <class Pose>
void MaintainedMap<Pose>::Move(int map, const Pose& frame) {
  last_trial_.reset();
  for (auto& [key, j] : junctions_) {
    if (map_of_[key >> 32] == map) j.x = frame * j.x;
  }
}

template <class Pose>
MinimizeResult MaintainedMap<Pose>::Optimize() {
  last_trial_.reset();
  std::vector<int> all;
  all.reserve(junctions_.size());
  for (const auto& [key, j] : junctions_) all.push_back(j.pose);
  return Minimize(all, {}).minimize;
}

template class MaintainedMap<Pose2>;
template class MaintainedMap<Pose3>;

}  // namespace rrr
