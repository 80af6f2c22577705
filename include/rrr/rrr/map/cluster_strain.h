// Which accepted clusters a trial against the map strains, and how much.
#ifndef RRR_RRR_MAP_CLUSTER_STRAIN_H_
#define RRR_RRR_MAP_CLUSTER_STRAIN_H_

#include <functional>
#include <utility>
#include <vector>

#include "rrr/rrr/map/maintained_map.h"

namespace rrr {

// The strain of each cluster whose loops are in `map_loops` (a MapTrial's):
// the rise of its loops' errors, Σ (after − before) over them, divided by
// `gate_of_cluster`(cluster), as RRR's consistency index normalizes errors.
// Returns (strain, cluster) for the clusters strained more than `above`,
// the most strained first (ties: the higher cluster index first).
// `cluster_of_loop` maps each graph loop index to its cluster.
std::vector<std::pair<double, int>> ClustersStrainedAbove(
    const std::vector<MapTrial::LoopStrain>& map_loops,
    const std::vector<int>& cluster_of_loop,
    const std::function<double(int)>& gate_of_cluster, double above);

}  // namespace rrr

#endif  // RRR_RRR_MAP_CLUSTER_STRAIN_H_
