// The map procedure over a whole graph, as the node would see it.
#ifndef RRR_RRR_MAP_VERIFY_WITH_MAP_H_
#define RRR_RRR_MAP_VERIFY_WITH_MAP_H_

#include <vector>

#include "rrr/graph/pose_graph.h"
#include "rrr/rrr/map/map_verifier.h"
#include "rrr/rrr/options.h"
#include "rrr/rrr/verdict.h"

namespace rrr {

// Runs the map procedure over `graph`, one odometry chain or several, as the
// node would see it: its poses in `order` (ArrivalOrder; the graph's if
// empty), each loop candidate right after its later pose, an update after
// every pose, then Finish() (FeedInArrivalOrder). Returns the decisions in
// graph.loops() indices; sets `*map` to the final map's estimates (each
// pose in its map's frame) and `*stats` if given. Throws
// std::invalid_argument if `options` do not validate.
template <class Pose>
Verdict VerifyWithMap(const PoseGraph<Pose>& graph, const RrrOptions& options,
                      std::vector<Pose>* map = nullptr,
                      MapVerifierStats* stats = nullptr,
                      const std::vector<int>& order = {});

}  // namespace rrr

#endif  // RRR_RRR_MAP_VERIFY_WITH_MAP_H_
