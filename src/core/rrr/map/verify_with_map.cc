#include "rrr/rrr/map/verify_with_map.h"

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"

namespace rrr {

template <class Pose>
Verdict VerifyWithMap(const PoseGraph<Pose>& graph, const RrrOptions& options,
                      std::vector<Pose>* map, MapVerifierStats* stats,
                      const std::vector<int>& order) {
  MapVerifier<Pose> verifier(options);
  const std::vector<int> loop_of_candidate =
      FeedInArrivalOrder(graph, &verifier, 1, nullptr, 0, order);
  Verdict verdict = VerdictOf(verifier, loop_of_candidate,
                              static_cast<int>(graph.loops().size()));
  // The verifier's pose k is the k-th to arrive: graph pose order[k].
  if (!order.empty()) {
    for (DecisionReason& reason : verdict.reasons) {
      if (reason.pose >= 0) reason.pose = order[reason.pose];
    }
  }
  if (map) {
    const std::vector<Pose> arrived = verifier.Map();
    *map = arrived;
    for (size_t k = 0; k < order.size(); ++k) (*map)[order[k]] = arrived[k];
  }
  if (stats) *stats = verifier.stats();
  return verdict;
}

template Verdict VerifyWithMap(const PoseGraph<Pose2>&, const RrrOptions&,
                               std::vector<Pose2>*, MapVerifierStats*,
                               const std::vector<int>&);
template Verdict VerifyWithMap(const PoseGraph<Pose3>&, const RrrOptions&,
                               std::vector<Pose3>*, MapVerifierStats*,
                               const std::vector<int>&);

}  // namespace rrr
