// The maps that odometry chains make once loops join them: each chain's frame
// in its map's, and each map minimized.
#ifndef RRR_SOLVER_CHAIN_MAPS_H_
#define RRR_SOLVER_CHAIN_MAPS_H_

#include <vector>

#include "rrr/graph/chain_spans.h"
#include "rrr/graph/pose_graph.h"
#include "rrr/solver/convergence.h"

namespace rrr {

// Two chains and the loops between them.
template <class Pose>
struct ChainPair {
  int first = 0;                // chain index
  int second = 0;               // chain index, > first
  std::vector<int> candidates;  // loop indices between them, ascending
  std::vector<int> accepted;    // of those, ascending
  std::vector<int> joined_by;   // the clusters that joined them, if any
  bool joined = false;
  // When joined: the second chain's frame in the first's, so that
  // x_first_frame = relative · x_second_frame.
  Pose relative;
};

// The chains of a graph, the pairs of them that loops join and the maps they
// make.
template <class Pose>
struct ChainMaps {
  std::vector<ChainSpan> chains;
  std::vector<ChainPair<Pose>> pairs;  // every pair with candidates
  // The map each chain ended in: the lowest index of the chains joined with
  // it (itself if joined with none). A map is in the frame of its lowest
  // chain; chains never joined stay apart, each in its own frame.
  std::vector<int> map_of_chain;
  std::vector<Pose> estimates;  // every pose, in its map's frame
  // Each map's final minimization, in the order of their lowest chains.
  std::vector<MinimizeResult> minimized;
};

// Each chain's frame in the frame of chain `root` through the joined `pairs`
// (x_root_frame = frames[c] · x_c_frame); the identity where none leads.
template <class Pose>
std::vector<Pose> FramesIn(const std::vector<ChainPair<Pose>>& pairs,
                           int num_chains, int root);

// Given `maps->chains`, `maps->pairs` (which are joined, and their relative
// poses) and `maps->estimates` (each chain in its own frame): sets
// map_of_chain, and minimizes each map, its chains placed in its lowest
// chain's frame, with the loops of `accepted` inside it (indices into
// graph.loops()); `estimates` and `minimized` receive the minima. With
// `only_map` >= 0, only the map of that lowest chain is minimized (and is
// the one entry of `minimized`).
template <class Pose>
void MinimizeMaps(const PoseGraph<Pose>& graph,
                  const std::vector<int>& accepted, ChainMaps<Pose>* maps,
                  int only_map = -1);

}  // namespace rrr

#endif  // RRR_SOLVER_CHAIN_MAPS_H_
