#include "rrr/rrr/map/verify_with_map.h"

#include <algorithm>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"

namespace rrr {

template <class Pose>
Verdict VerifyWithMap(const PoseGraph<Pose>& graph, const RrrOptions& options,
                      std::vector<Pose>* map, MapVerifierStats* stats) {
  MapVerifier<Pose> verifier(options);
  const std::vector<int> loop_of_candidate =
      FeedInArrivalOrder(graph, &verifier);
  return VerdictOfVerifier(&verifier, loop_of_candidate,
                           static_cast<int>(graph.loops().size()), map, stats);
}

template <class Pose>
Verdict VerdictOfVerifier(MapVerifier<Pose>* verifier,
                          const std::vector<int>& loop_of_candidate,
                          int num_loops, std::vector<Pose>* map,
                          MapVerifierStats* stats) {
  Verdict verdict;
  verdict.cluster_of_loop.assign(num_loops, -1);
  verdict.reasons.resize(num_loops);
  for (int c = 0; c < verifier->num_candidates(); ++c) {
    const int k = loop_of_candidate[c];
    if (k < 0) continue;  // waiting for a pose
    verdict.cluster_of_loop[k] = verifier->cluster_of(c);
    verdict.reasons[k] = verifier->reason(c);
    (verifier->state(c) == LoopState::kAccepted ? verdict.accepted
                                                : verdict.rejected)
        .push_back(k);
  }
  std::sort(verdict.accepted.begin(), verdict.accepted.end());
  std::sort(verdict.rejected.begin(), verdict.rejected.end());
  verdict.clusters.resize(verifier->num_clusters());
  for (size_t k = 0; k < verdict.cluster_of_loop.size(); ++k) {
    if (verdict.cluster_of_loop[k] < 0) continue;
    verdict.clusters[verdict.cluster_of_loop[k]].loops.push_back(
        static_cast<int>(k));
  }
  if (map) *map = verifier->Map();
  if (stats) {
    *stats = verifier->stats();
    stats->noise_scale = verifier->noise_scale();
    stats->group_noise_scale = verifier->group_noise_scale();
    stats->noise_scale_source = verifier->noise_scale_source();
    stats->a_posteriori_scale = verifier->APosterioriScale();
  }
  return verdict;
}

template Verdict VerifyWithMap(const PoseGraph<Pose2>&, const RrrOptions&,
                               std::vector<Pose2>*, MapVerifierStats*);
template Verdict VerifyWithMap(const PoseGraph<Pose3>&, const RrrOptions&,
                               std::vector<Pose3>*, MapVerifierStats*);
template Verdict VerdictOfVerifier(MapVerifier<Pose2>*, const std::vector<int>&,
                                   int, std::vector<Pose2>*, MapVerifierStats*);
template Verdict VerdictOfVerifier(MapVerifier<Pose3>*, const std::vector<int>&,
                                   int, std::vector<Pose3>*, MapVerifierStats*);

}  // namespace rrr
