// A graph's poses given to an online verifier as a robot would give them.
#ifndef RRR_CORE_TESTING_FEED_POSES_H_
#define RRR_CORE_TESTING_FEED_POSES_H_

#include <algorithm>
#include <functional>

#include "rrr/graph/odometry_chain.h"
#include "rrr/graph/pose_graph.h"
#include "rrr/rrr/online_verifier.h"

namespace rrr::testing {

// Gives `verifier` the poses of `graph` from `first` to `last` - 1 and each
// loop after its later pose (in arrival order), calling `after_pose` with
// each pose index given, if set.
template <class Pose>
void FeedPoses(const PoseGraph<Pose>& graph, int first, int last,
               OnlineVerifier<Pose>* verifier,
               const std::function<void(int)>& after_pose = nullptr) {
  const OdometryChain<Pose> chain = ChainOf(graph);
  for (int p = first; p < last; ++p) {
    if (p == 0) {
      verifier->AddFirstPose(graph.ids()[0], graph.estimates()[0]);
    } else {
      const Constraint<Pose> step = chain.Between(p - 1, p);
      verifier->AddOdometry(step.measurement, step.information);
    }
    for (const auto& e : graph.loops()) {
      if (std::max(e.from, e.to) == p) {
        verifier->AddLoop(graph.ids()[e.from], graph.ids()[e.to], e.measurement,
                          e.information);
      }
    }
    if (after_pose) after_pose(p);
  }
}

}  // namespace rrr::testing

#endif  // RRR_CORE_TESTING_FEED_POSES_H_
