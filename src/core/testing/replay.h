// Replaying a graph through an online verifier, for tests.
#ifndef RRR_CORE_TESTING_REPLAY_H_
#define RRR_CORE_TESTING_REPLAY_H_

#include <set>
#include <utility>
#include <vector>

#include "rrr/rrr/online_verifier.h"
#include "rrr/rrr/options.h"

namespace rrr::testing {

using Pairs = std::set<std::pair<PoseId, PoseId>>;

// Feeds `graph` to a verifier (FeedInArrivalOrder) and counts the reversed
// decisions in each direction.
template <class Verifier, class Pose>
struct Replay {
  Verifier verifier;
  int accepted_then_rejected = 0, rejected_then_accepted = 0;

  Replay(const PoseGraph<Pose>& graph, const RrrOptions& options,
         int update_every = 1, int loop_lag = 0)
      : verifier(options) {
    FeedInArrivalOrder(
        graph, &verifier, update_every,
        [this](const std::vector<DecisionChange>& changes) {
          for (const auto& c : changes) {
            accepted_then_rejected += c.previous == LoopState::kAccepted;
            rejected_then_accepted += c.previous == LoopState::kRejected;
          }
        },
        loop_lag);
  }
  // The end ids of the accepted candidates.
  Pairs Accepted() const {
    Pairs out;
    for (int c = 0; c < verifier.num_candidates(); ++c) {
      if (verifier.state(c) == LoopState::kAccepted) {
        out.insert(verifier.ends_of(c));
      }
    }
    return out;
  }
};

}  // namespace rrr::testing

#endif  // RRR_CORE_TESTING_REPLAY_H_
