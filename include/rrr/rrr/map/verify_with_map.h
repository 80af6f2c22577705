// The map procedure over a whole graph, as the node would see it.
#ifndef RRR_RRR_MAP_VERIFY_WITH_MAP_H_
#define RRR_RRR_MAP_VERIFY_WITH_MAP_H_

#include <vector>

#include "rrr/graph/pose_graph.h"
#include "rrr/rrr/map/map_verifier.h"
#include "rrr/rrr/options.h"
#include "rrr/rrr/verdict.h"

namespace rrr {

// The map procedure over `graph` (one chain or several) as the node sees
// it: FeedInArrivalOrder in `order` (the graph's if empty). Returns the
// decisions by graph.loops() index; sets `*map` to the final map (each pose
// in its map's frame) and `*stats` if given. Throws std::invalid_argument
// if `options` do not validate.
template <class Pose>
Verdict VerifyWithMap(const PoseGraph<Pose>& graph, const RrrOptions& options,
                      std::vector<Pose>* map = nullptr,
                      MapVerifierStats* stats = nullptr,
                      const std::vector<int>& order = {});

}  // namespace rrr

#endif  // RRR_RRR_MAP_VERIFY_WITH_MAP_H_
