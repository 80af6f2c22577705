// Which candidates a stream of decision changes must carry.
#ifndef RRR_RRR_DECISION_DELTA_H_
#define RRR_RRR_DECISION_DELTA_H_

#include <vector>

#include "rrr/rrr/online_verifier.h"

namespace rrr {

// For a stream of messages each carrying some candidates with their state
// now (a node's ~decisions): which candidates the next message must carry
// so that a consumer who applies the messages in order knows every
// candidate's state, cluster and whether it waits for a pose. Those are the
// ones that changed state, the ones never carried, and the ones whose
// cluster or waiting changed since they were carried. The work of a call is
// bounded by what it returns plus the candidates carried without a cluster
// (waiting, not clustered yet, or between two chains), not by all the
// candidates, unless the verifier gave clustered loops other clusters since
// the last call (num_reclusterings(); the published procedure), when every
// candidate is looked at.
class DecisionDelta {
 public:
  // The candidate numbers the next message carries, ascending, given the
  // changes of the updates since the last call; the verifier's state now is
  // then taken as carried.
  template <class Pose>
  std::vector<int> Next(const OnlineVerifier<Pose>& verifier,
                        const std::vector<DecisionChange>& changes);

 private:
  // Per candidate carried (0 .. size - 1): the cluster it was carried with
  // and whether it was waiting.
  std::vector<int> cluster_;
  std::vector<bool> waiting_;
  std::vector<int> unclustered_;  // carried with cluster -1, ascending
  int reclusterings_ = 0;         // the verifier's count when last called
};

}  // namespace rrr

#endif  // RRR_RRR_DECISION_DELTA_H_
