// MapVerifier, step 5: the whole-map minimization and what it calls for
// (the review of split clusters and the re-opening of clusters whose
// standing the map's estimate or scale has changed). The other steps are in
// map_verifier.cc.
#include <algorithm>
#include <iterator>
#include <utility>
#include <vector>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/rrr/map/map_verifier.h"

namespace rrr {

template <class Pose>
void MapVerifier<Pose>::OptimizeMap() {
  if (!map_) return;
  ++stats_.optimizations;
  this->CountSolves(1);
  const MinimizeResult result = map_->Optimize();
  if (!result.converged) ++stats_.not_converged;
  // At the whole map's minimum the accepted clusters' errors give the
  // a-posteriori scale, which their trials' increases overstate.
  scale_.SetClusterSamplesAtMinimum(AcceptedAtEstimate(), result.final_chi2);
  accepted_since_optimize_ = 0;
  reopen_needed_ = true;
  review_needed_ = true;
}

template <class Pose>
void MapVerifier<Pose>::ReviewSplitClusters() {
  review_needed_ = false;
  const int e = Pose::kDof;
  for (size_t i = 0; i < records_.size(); ++i) {
    const int c = static_cast<int>(i);
    ClusterRecord& record = records_[c];
    if (record.status != Status::kAccepted ||
        record.left_out.size() * kSplitRatio < record.survivors.size() ||
        accepted_clusters_ < kReviewGrowth * record.reviewed_at) {
      continue;
    }
    ++stats_.reviewed;
    record.reviewed_at = accepted_clusters_;
    const double gate = Gate(e * static_cast<int>(record.survivors.size()));
    if (Fits(TryAgainstMap(record.survivors, gate), gate)) continue;
    LeaveMap(c);
    scale_.RemoveClusterSample(c);
    RegroupAgainstMap(c);
    reopen_needed_ = true;
  }
}

template <class Pose>
void MapVerifier<Pose>::RegroupAgainstMap(int c) {
  ++stats_.regrouped;
  ClusterRecord& record = records_[c];
  std::vector<int> all = record.survivors;
  all.insert(all.end(), record.left_out.begin(), record.left_out.end());
  std::sort(all.begin(), all.end());
  // Each link alone, then the group grown from the one that fits best.
  const double one_link = Gate(Pose::kDof);
  std::vector<std::pair<double, int>> alone;  // (Δ, loop) of those that fit
  for (const int loop : all) {
    const MapTrial trial = TryAgainstMap({loop}, one_link);
    if (Fits(trial, one_link)) alone.emplace_back(trial.increase, loop);
  }
  std::sort(alone.begin(), alone.end());
  std::vector<int> group;
  for (const auto& [increase, loop] : alone) {
    std::vector<int> grown = group;
    grown.insert(std::upper_bound(grown.begin(), grown.end(), loop), loop);
    const double gate = Gate(Pose::kDof * static_cast<int>(grown.size()));
    if (group.empty() || Fits(TryAgainstMap(grown, gate), gate)) {
      group = std::move(grown);
    }
  }
  bool accepted = false;
  if (!group.empty()) TryPart(c, group, &accepted);
  if (!accepted) {
    SetAside(c);
    return;
  }
  record.left_out.clear();
  std::set_difference(all.begin(), all.end(), group.begin(), group.end(),
                      std::back_inserter(record.left_out));
}

template <class Pose>
void MapVerifier<Pose>::ReopenWhileNeeded() {
  if (review_needed_) ReviewSplitClusters();
  // Each round may change the map and call for another; a few suffice.
  for (int round = 0; round < kMostReopenRounds && reopen_needed_; ++round) {
    Reopen();
  }
}

template <class Pose>
void MapVerifier<Pose>::Reopen() {
  reopen_needed_ = false;
  const int e = Pose::kDof;
  const double scale = NoiseScaleAt(decision_pose_);
  for (size_t c = 0; c < records_.size(); ++c) {
    ClusterRecord& record = records_[c];
    if (record.status == Status::kRejected) {
      if (scale >= kRejudgeScaleRatio * record.judged_scale) {
        ++stats_.reopened;
        JudgeCluster(static_cast<int>(c));
      }
      continue;
    }
    if (record.status == Status::kAccepted &&
        record.judged_scale >= kRejudgeScaleRatio * scale) {
      // Accepted under a scale at least twice today's: judged again, its
      // noise-scale sample kept until the new decision.
      ++stats_.reopened;
      LeaveMap(static_cast<int>(c));
      JudgeCluster(static_cast<int>(c));
      if (record.status != Status::kAccepted) {
        scale_.RemoveClusterSample(static_cast<int>(c));
      }
      continue;
    }
    const int dof = e * static_cast<int>(record.survivors.size());
    const bool strained = record.status == Status::kAccepted &&
                          ClusterChi2AtEstimate(c) >= Gate(dof);
    const bool fits = record.status == Status::kSetAside &&
                      ClusterChi2AtEstimate(c) < Gate(dof);
    if (!strained && !fits) continue;
    ++stats_.reopened;
    if (strained) {
      LeaveMap(static_cast<int>(c));
      scale_.RemoveClusterSample(static_cast<int>(c));
    }
    JudgeAgainstMap(static_cast<int>(c));
  }
}

#define RRR_INSTANTIATE_REOPEN(Pose)                         \
  template void MapVerifier<Pose>::OptimizeMap();            \
  template void MapVerifier<Pose>::ReviewSplitClusters();    \
  template void MapVerifier<Pose>::RegroupAgainstMap(int c); \
  template void MapVerifier<Pose>::ReopenWhileNeeded();      \
  template void MapVerifier<Pose>::Reopen();
RRR_INSTANTIATE_REOPEN(Pose2)
RRR_INSTANTIATE_REOPEN(Pose3)
#undef RRR_INSTANTIATE_REOPEN

}  // namespace rrr
