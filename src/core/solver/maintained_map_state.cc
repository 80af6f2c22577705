// MaintainedMap's state written and read back (Save, Restore).
#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/solver/maintained_map.h"

namespace rrr {

template <class Pose>
void MaintainedMap<Pose>::Save(ByteWriter* out) const {
  out->Int(num_chains());
  out->Int(static_cast<std::int64_t>(junctions_.size()));
  for (const auto& [key, j] : junctions_) {
    out->Int(j.pose);
    out->PoseParts(j.x);
    out->Ints(j.loops);
    out->Int(j.temporary);
  }
  std::vector<int> in_map;
  for (size_t k = 0; k < in_map_.size(); ++k) {
    if (in_map_[k]) in_map.push_back(static_cast<int>(k));
  }
  out->Ints(in_map);
  out->Int(last_trial_ ? 1 : 0);
  if (!last_trial_) return;
  out->Ints(last_trial_->loops);
  out->Int(last_trial_->radius);
  out->Int(static_cast<std::int64_t>(last_trial_->estimate.size()));
  for (const auto& [pose, x] : last_trial_->estimate) {
    out->Int(pose);
    out->PoseParts(x);
  }
}

template <class Pose>
void MaintainedMap<Pose>::Restore(ByteReader* in) {
  const auto checked_pose = [&](std::int64_t pose) {
    if (pose < 0 || pose >= graph_.num_poses()) {
      throw std::runtime_error("the map names pose " + std::to_string(pose) +
                               " of a graph of " +
                               std::to_string(graph_.num_poses()));
    }
    return static_cast<int>(pose);
  };
  const auto checked_loops = [&](std::vector<int> loops) {
    for (const int k : loops) {
      if (k < 0 || k >= static_cast<int>(graph_.loops().size())) {
        throw std::runtime_error("the map names loop " + std::to_string(k) +
                                 " of a graph of " +
                                 std::to_string(graph_.loops().size()));
      }
    }
    return loops;
  };
  const std::int64_t taken = in->Int("the chains taken in");
  if (taken < 0 || taken > chains_.num_chains()) {
    throw std::runtime_error("the map takes in " + std::to_string(taken) +
                             " chains of " +
                             std::to_string(chains_.num_chains()));
  }
  junctions_.clear();
  const size_t n = in->Count("junctions", sizeof(typename Pose::Parts));
  for (size_t k = 0; k < n; ++k) {
    const int pose = checked_pose(in->Int("a junction"));
    if (chains_.chain_of(pose) >= taken) {
      throw std::runtime_error("the map places pose " + std::to_string(pose) +
                               " of a chain it has not taken in");
    }
    Junction& j = junctions_[chains_.Key(pose)];
    j.pose = pose;
    j.x = in->template PoseParts<Pose>("a junction's estimate");
    j.loops = checked_loops(in->Ints("a junction's loops"));
    j.temporary = static_cast<int>(in->Int("a junction's tries"));
  }
  in_map_.assign(graph_.loops().size(), false);
  num_loops_ = 0;
  between_.clear();
  for (const int k : checked_loops(in->Ints("the map's loops"))) {
    in_map_[k] = true;
    ++num_loops_;
    const int a = chains_.chain_of(graph_.loops()[k].from);
    const int b = chains_.chain_of(graph_.loops()[k].to);
    if (std::max(a, b) >= taken) {
      throw std::runtime_error("the map's loop " + std::to_string(k) +
                               " reaches a chain it has not taken in");
    }
    if (a != b) ++between_[{std::min(a, b), std::max(a, b)}];
  }
  map_of_.assign(taken, 0);
  map_of_ = Maps(-1, -1);
  // What the map's operations rely on: every chain's first pose is a
  // junction, no junction is held by a negative count of tries, and each of the
  // map's loops is listed at the junctions of its two ends, once each.
  std::vector<std::pair<int, int>> listed, ends;  // (junction, loop)
  for (const auto& [key, j] : junctions_) {
    const int pose = j.pose;
    if (j.temporary < 0) {
      throw std::runtime_error("the junction at pose " + std::to_string(pose) +
                               " is held by " + std::to_string(j.temporary) +
                               " tries");
    }
    for (const int k : j.loops) listed.emplace_back(pose, k);
  }
  for (size_t k = 0; k < in_map_.size(); ++k) {
    if (!in_map_[k]) continue;
    ends.emplace_back(graph_.loops()[k].from, static_cast<int>(k));
    ends.emplace_back(graph_.loops()[k].to, static_cast<int>(k));
  }
  std::sort(listed.begin(), listed.end());
  std::sort(ends.begin(), ends.end());
  if (listed != ends) {
    throw std::runtime_error(
        "the map's junctions do not list its loops at their ends");
  }
  for (int c = 0; c < num_chains(); ++c) {
    const int first = chains_.poses(c).front();
    if (junctions_.count(chains_.Key(first)) == 0) {
      throw std::runtime_error("the map has no junction at pose " +
                               std::to_string(first) +
                               ", the first of a chain");
    }
  }
  last_trial_.reset();
  if (in->Int("whether a trial is kept") == 0) return;
  last_trial_ = std::make_unique<KeptTrial>();
  last_trial_->loops = checked_loops(in->Ints("the kept trial's loops"));
  last_trial_->radius = static_cast<int>(in->Int("the kept trial's radius"));
  last_trial_->estimate.resize(
      in->Count("the kept trial's estimate", sizeof(typename Pose::Parts)));
  // A trial places junctions and its loops' ends, which are junctions only
  // while it runs (KeepTrial makes them junctions again).
  const std::vector<int> trial_ends = PosesTouched(graph_, last_trial_->loops);
  for (auto& [pose, x] : last_trial_->estimate) {
    pose = checked_pose(in->Int("a kept trial's pose"));
    x = in->template PoseParts<Pose>("a kept trial's estimate");
    if (junctions_.count(chains_.Key(pose)) == 0 &&
        !std::binary_search(trial_ends.begin(), trial_ends.end(), pose)) {
      throw std::runtime_error("the kept trial places pose " +
                               std::to_string(pose) +
                               ", which is neither a junction nor an end of "
                               "its loops");
    }
  }
}

template void MaintainedMap<Pose2>::Save(ByteWriter*) const;
template void MaintainedMap<Pose3>::Save(ByteWriter*) const;
template void MaintainedMap<Pose2>::Restore(ByteReader*);
template void MaintainedMap<Pose3>::Restore(ByteReader*);

}  // namespace rrr
