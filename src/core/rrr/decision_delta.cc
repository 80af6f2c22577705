#include "rrr/rrr/decision_delta.h"

#include <algorithm>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"

namespace rrr {

template <class Pose>
std::vector<int> DecisionDelta::Next(
    const OnlineVerifier<Pose>& verifier,
    const std::vector<DecisionChange>& changes) {
  const int carried = static_cast<int>(cluster_.size());
  std::vector<int> next;
  for (const DecisionChange& change : changes) {
    if (change.candidate < carried) next.push_back(change.candidate);
  }
  const auto moved = [&](int c) {
    return verifier.cluster_of(c) != cluster_[c] ||
           verifier.waiting(c) != waiting_[c];
  };
  if (verifier.num_reclusterings() != reclusterings_) {
    reclusterings_ = verifier.num_reclusterings();
    for (int c = 0; c < carried; ++c) {
      if (moved(c)) next.push_back(c);
    }
  } else {
    for (const int c : unclustered_) {
      if (moved(c)) next.push_back(c);
    }
  }
  for (int c = carried; c < verifier.num_candidates(); ++c) next.push_back(c);
  std::sort(next.begin(), next.end());
  next.erase(std::unique(next.begin(), next.end()), next.end());

  cluster_.resize(verifier.num_candidates());
  waiting_.resize(verifier.num_candidates());
  std::vector<int> unclustered;
  for (const int c : next) {
    cluster_[c] = verifier.cluster_of(c);
    waiting_[c] = verifier.waiting(c);
  }
  // Those carried before and still without a cluster, and those just
  // carried without one (both ascending; merged).
  for (const int c : unclustered_) {
    if (cluster_[c] < 0) unclustered.push_back(c);
  }
  for (const int c : next) {
    if (cluster_[c] < 0) unclustered.push_back(c);
  }
  std::sort(unclustered.begin(), unclustered.end());
  unclustered.erase(std::unique(unclustered.begin(), unclustered.end()),
                    unclustered.end());
  unclustered_ = std::move(unclustered);
  return next;
}

template std::vector<int> DecisionDelta::Next(
    const OnlineVerifier<Pose2>&, const std::vector<DecisionChange>&);
template std::vector<int> DecisionDelta::Next(
    const OnlineVerifier<Pose3>&, const std::vector<DecisionChange>&);

}  // namespace rrr
