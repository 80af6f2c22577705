// MapVerifier: parts 2 to 4 of the rule (the links of a cluster that agree,
// conflict, the arbiter). The record, the inputs and the map are in
// map_verifier.cc, the noise scale (part 1) in noise_scale.cc.
#include <algorithm>
#include <numeric>
#include <utility>
#include <vector>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/rrr/map/map_verifier.h"
#include "rrr/solver/condensed_solve.h"

namespace rrr {

template <class Pose>
double MapVerifier<Pose>::Gate(Against against, size_t links) const {
  const bool one_link_on_the_map = against == Against::kMap && links == 1;
  return (one_link_on_the_map ? MapScaleAt(decision_pose_)
                              : GroupScaleAt(decision_pose_)) *
         chi2_(Pose::kDof * static_cast<int>(links));
}

template <class Pose>
MapTrial MapVerifier<Pose>::Test(const std::vector<int>& links,
                                 Against against) {
  MapTrial trial;
  if (against == Against::kMap) {
    ++stats_.trials;
    this->CountSolves(1);
    trial = map_->Try(links, options_.map_radius, Gate(against, links.size()));
  } else {
    ++stats_.own_solves;
    this->CountSolves(1);
    const CondensedErrors own = SolveCondensed(this->graph(), this->chains(),
                                               links, options_.convergence);
    trial.free_frames = own.free_frames;
    trial.minimize = own.minimize;
    trial.minimize.solved = own.errors.solved;
    trial.increase = own.errors.total_chi2;
    trial.loop_chi2 = own.errors.loop_chi2;
  }
  if (!trial.minimize.converged) ++stats_.not_converged;
  return trial;
}

template <class Pose>
bool MapVerifier<Pose>::Passes(const MapTrial& trial, Against against) const {
  const double one_link = Gate(against, 1);
  const size_t checked = trial.loop_chi2.size() - trial.free_frames;
  return trial.minimize.solved &&
         (checked == 0 || trial.increase < Gate(against, checked)) &&
         std::all_of(trial.loop_chi2.begin(), trial.loop_chi2.end(),
                     [&](double d2) { return d2 < one_link; });
}

template <class Pose>
MapTrial MapVerifier<Pose>::AtEstimate(const std::vector<int>& links) const {
  MapTrial at;
  for (const int loop : links) {
    at.loop_chi2.push_back(map_->LoopChi2(loop));
    at.increase += at.loop_chi2.back();
  }
  return at;
}

template <class Pose>
std::vector<int> MapVerifier<Pose>::KeepAgreeing(std::vector<int> links,
                                                 Against against,
                                                 MapTrial* trial) {
  const bool map = against == Against::kMap;
  while (!Passes(*trial, against) && trial->minimize.solved &&
         links.size() > 1) {
    const auto k =
        std::max_element(trial->loop_chi2.begin(), trial->loop_chi2.end()) -
        trial->loop_chi2.begin();
    std::vector<int> rest = links;
    rest.erase(rest.begin() + k);
    MapTrial without = Test(rest, against);
    const double brings = trial->increase - without.increase;
    if (!without.minimize.solved || brings < Gate(against, 1)) break;
    Record({links[k]}, map ? DecisionTest::kMapLink : DecisionTest::kOwnLink,
           brings);
    links = std::move(rest);
    *trial = std::move(without);
  }
  if (!Passes(*trial, against)) {
    Record(links, map ? DecisionTest::kMap : DecisionTest::kOwn,
           trial->increase, trial->free_frames);
    links.clear();
  }
  return links;
}

template <class Pose>
void MapVerifier<Pose>::JudgeCluster(int c) {
  ClusterRecord& record = records_[c];
  record.status = Status::kRefused;
  record.accepted.clear();
  touched_.push_back(c);
  Forget(c);
  // Between two maps that no join relates, the map cannot decide between
  // groups: the first that agrees waits for the join rule.
  const auto [a, b] = ChainsOf(c);
  const bool apart = map_->MapOf(a) != map_->MapOf(b);
  std::vector<int> links;
  for (const int loop : clustering_.clusters()[c].loops) {
    if (alone_chi2_[loop] >= Gate(Against::kOdometry, 1)) {
      Record({loop}, DecisionTest::kAlone, alone_chi2_[loop]);
    } else {
      links.push_back(loop);
    }
  }
  if (links.empty()) return;
  // The odometry alone may split the cluster: a revisit and a false group
  // that looks like one can each agree with themselves. The links it left
  // out get the same test, and the map decides between the two groups, the
  // larger first.
  std::vector<std::vector<int>> groups;
  while (!links.empty()) {
    MapTrial trial = Test(links, Against::kOdometry);
    std::vector<int> kept = KeepAgreeing(links, Against::kOdometry, &trial);
    std::vector<int> left_out;
    for (const int loop : links) {
      if (reasons_[loop].test == DecisionTest::kOwnLink &&
          std::find(kept.begin(), kept.end(), loop) == kept.end()) {
        left_out.push_back(loop);
      }
    }
    if (!kept.empty()) groups.push_back(std::move(kept));
    if (groups.size() == 2 || apart) break;
    links = std::move(left_out);
  }
  if (apart) {
    if (groups.empty()) return;
    Hold(c, groups.front());
    JudgeJoin(a, b);
    return;
  }
  std::stable_sort(
      groups.begin(), groups.end(),
      [](const auto& a, const auto& b) { return a.size() > b.size(); });
  for (std::vector<int>& group : groups) {
    JudgeAgainstMap(c, std::move(group));
    if (record.status == Status::kAccepted) return;
  }
}

template <class Pose>
void MapVerifier<Pose>::JudgeAgainstMap(int c, std::vector<int> links) {
  const MapTrial at_estimate = AtEstimate(links);
  if (Passes(at_estimate, Against::kMap)) {
    ++stats_.quick_accepts;
    Accept(c, links, at_estimate.increase, false);
    return;
  }
  MapTrial trial = Test(links, Against::kMap);
  if (Passes(trial, Against::kMap)) {
    Accept(c, links, trial.increase, true);
    return;
  }
  if (links.size() > 1) {
    // A group may fail only by the region's held border.
    int tries = 0;
    const MapTrial wide = map_->Widen(
        trial, links, options_.map_radius, Gate(Against::kMap, links.size()),
        Significant(),
        [&](const MapTrial& t) { return Passes(t, Against::kMap); }, &tries);
    stats_.trials += tries;
    this->CountSolves(tries);
    if (Passes(wide, Against::kMap)) {
      Accept(c, links, wide.increase, true);
      return;
    }
  }
  const MapTrial failed = trial;
  std::vector<int> kept = KeepAgreeing(links, Against::kMap, &trial);
  if (Outweigh(c, links, failed, kept.size())) return;
  if (kept.empty()) return;
  // The conflict's trials replaced the one to keep.
  trial = Test(kept, Against::kMap);
  if (!Passes(trial, Against::kMap)) {
    Record(kept, DecisionTest::kMap, trial.increase);
    return;
  }
  Accept(c, kept, trial.increase, true);
}

template <class Pose>
bool MapVerifier<Pose>::Outweigh(int c, const std::vector<int>& links,
                                 const MapTrial& failed, size_t kept) {
  if (!failed.minimize.solved) return false;
  // RRR's consistency index of the links in the joint solve: what they
  // bring to the map over their gate.
  const double theirs = failed.increase / Gate(Against::kMap, links.size());
  // The accepted clusters whose links' errors the trial raised, the most
  // (over their gate) first.
  std::vector<std::pair<int, double>> rise;  // (cluster, Δd²)
  for (const auto& l : failed.map_loops) {
    rise.emplace_back(this->cluster_of_loop_[l.loop], l.after - l.before);
  }
  std::sort(rise.begin(), rise.end());
  std::vector<std::pair<double, int>> strained;  // (strain, cluster)
  for (size_t k = 0; k < rise.size();) {
    const int a = rise[k].first;
    double sum = 0.0;
    for (; k < rise.size() && rise[k].first == a; ++k) sum += rise[k].second;
    if (sum > 0.0) {
      strained.emplace_back(
          sum / Gate(Against::kMap, records_[a].accepted.size()), a);
    }
  }
  std::sort(strained.rbegin(), strained.rend());
  // Set aside in turn while the links do not fit. A cluster whose removal
  // does not lower the links' Δ by more than Significant() is not in the
  // conflict (the failed trial strains the true clusters a false group bent
  // as much as the group itself) and goes back at once. What the set-aside
  // clusters R bring to the map with the links is, by the additivity of
  // minimal errors, Δ(R) + Δ(links with R) − Δ(links without R), with Δ(R)
  // as when they were accepted; over R's gate, it is their consistency
  // index in the joint solve.
  std::vector<int> removed;
  size_t removed_links = 0;
  double removed_brought = 0.0;
  double increase = failed.increase;  // Δ(links without R)
  for (const auto& [strain, a] : strained) {
    const std::vector<int>& accepted = records_[a].accepted;
    // A reversal must keep more links in the map than part 2 would.
    if (removed_links + accepted.size() + kept >= links.size()) continue;
    // Δ(links without R) >= 0 bounds their index from above: once it cannot
    // exceed the links' own, no trial is needed.
    const double brought =
        removed_brought + reasons_[accepted.front()].statistic;
    if ((brought + failed.increase) /
            Gate(Against::kMap, removed_links + accepted.size()) <=
        theirs) {
      break;
    }
    map_->Remove(accepted, options_.map_radius, Significant());
    const MapTrial without = Test(links, Against::kMap);
    if (without.minimize.solved &&
        increase - without.increase <= Significant()) {
      map_->Add(accepted, options_.map_radius, Significant());
      continue;
    }
    removed.push_back(a);
    removed_links += accepted.size();
    removed_brought = brought;
    if (without.minimize.solved) increase = without.increase;
    if (!Passes(without, Against::kMap)) continue;
    const double others =
        (removed_brought + failed.increase - without.increase) /
        Gate(Against::kMap, removed_links);
    if (others <= theirs) break;
    Accept(c, links, without.increase, true);
    for (const int r : removed) {
      ++stats_.reversals;
      Record(records_[r].accepted, DecisionTest::kOutweighed, others);
      for (const int loop : records_[r].accepted) {
        reasons_[loop].gate = theirs;
        reasons_[loop].by_cluster = c;
      }
      records_[r].status = Status::kRefused;
      records_[r].accepted.clear();
      scale_.RemoveClusterSample(r);
      touched_.push_back(r);
    }
    arbiter_due_ = true;
    return true;
  }
  for (auto it = removed.rbegin(); it != removed.rend(); ++it) {
    map_->Add(records_[*it].accepted, options_.map_radius, Significant());
  }
  return false;
}

template <class Pose>
void MapVerifier<Pose>::Arbitrate() {
  for (int round = 0; round < kMostArbiterRounds && arbiter_due_; ++round) {
    arbiter_due_ = ArbitrateOnce();
  }
  arbiter_due_ = false;
}

template <class Pose>
bool MapVerifier<Pose>::InDoubt(int c) const {
  const ClusterRecord& record = records_[c];
  if (record.status == Status::kAccepted) {
    // Its links were accepted together, with one reason: their Δ.
    const double delta = reasons_[record.accepted.front()].statistic;
    return delta >= Gate(Against::kMap, record.accepted.size()) ||
           !Passes(AtEstimate(record.accepted), Against::kMap);
  }
  const auto& loops = clustering_.clusters()[c].loops;
  return std::any_of(loops.begin(), loops.end(), [&](int loop) {
    return reasons_[loop].test == DecisionTest::kAlone &&
           reasons_[loop].statistic < Gate(Against::kOdometry, 1);
  });
}

template <class Pose>
bool MapVerifier<Pose>::ArbitrateOnce() {
  bool changed = false;
  for (size_t i = 0; i < records_.size(); ++i) {
    const int c = static_cast<int>(i);
    ClusterRecord& record = records_[c];
    if (record.status == Status::kPending || record.status == Status::kHeld) {
      continue;
    }
    const auto [a, b] = ChainsOf(c);
    if (map_->MapOf(a) != map_->MapOf(b)) continue;  // no estimate relates them
    if (InDoubt(c)) {
      ++stats_.rejudged;
      if (record.status == Status::kAccepted) LeaveMap(c);
      JudgeCluster(c);
      changed = true;
      continue;
    }
    // Refused links that the map's estimate now fits, each alone and with
    // the cluster's accepted links.
    std::vector<int> grown = record.accepted;
    for (const int loop : clustering_.clusters()[c].loops) {
      if (!std::binary_search(record.accepted.begin(), record.accepted.end(),
                              loop) &&
          alone_chi2_[loop] < Gate(Against::kOdometry, 1) &&
          map_->LoopChi2(loop) < Gate(Against::kMap, 1)) {
        grown.push_back(loop);
      }
    }
    if (grown.size() == record.accepted.size()) continue;
    const MapTrial at_estimate = AtEstimate(grown);
    if (!Passes(at_estimate, Against::kMap)) continue;
    ++stats_.rejudged;
    Accept(c, grown, at_estimate.increase, false);
    changed = true;
  }
  return changed;
}

// The members the other parts of MapVerifier call.
#define RRR_INSTANTIATE_RULE(Pose)                                             \
  template double MapVerifier<Pose>::Gate(Against, size_t) const;              \
  template MapTrial MapVerifier<Pose>::Test(const std::vector<int>&, Against); \
  template bool MapVerifier<Pose>::Passes(const MapTrial&, Against) const;     \
  template void MapVerifier<Pose>::JudgeCluster(int);                          \
  template void MapVerifier<Pose>::JudgeAgainstMap(int, std::vector<int>);     \
  template void MapVerifier<Pose>::Arbitrate();
RRR_INSTANTIATE_RULE(Pose2)
RRR_INSTANTIATE_RULE(Pose3)
#undef RRR_INSTANTIATE_RULE

}  // namespace rrr
