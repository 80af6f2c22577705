#include "rrr/rrr/map/verify_with_map.h"

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"

namespace rrr {

template <class Pose>
Verdict VerifyWithMap(const PoseGraph<Pose>& graph, const RrrOptions& options,
                      std::vector<Pose>* map, MapVerifierStats* stats) {
  MapVerifier<Pose> verifier(options);
  const std::vector<int> loop_of_candidate =
      FeedInArrivalOrder(graph, &verifier);
  Verdict verdict = VerdictOf(verifier, loop_of_candidate,
                              static_cast<int>(graph.loops().size()));
  if (map) *map = verifier.Map();
  if (stats) *stats = verifier.stats();
  return verdict;
}

template Verdict VerifyWithMap(const PoseGraph<Pose2>&, const RrrOptions&,
                               std::vector<Pose2>*, MapVerifierStats*);
template Verdict VerifyWithMap(const PoseGraph<Pose3>&, const RrrOptions&,
                               std::vector<Pose3>*, MapVerifierStats*);

}  // namespace rrr
