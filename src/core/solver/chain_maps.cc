#include "rrr/solver/chain_maps.h"

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/graph/disjoint_sets.h"
#include "rrr/io/g2o.h"
#include "rrr/solver/pose_graph_solver.h"

namespace rrr {

template <class Pose>
std::vector<Pose> FramesIn(const std::vector<ChainPair<Pose>>& pairs,
                           int num_chains, int root) {
  std::vector<bool> placed(num_chains, false);
  std::vector<Pose> frame(num_chains);
  placed[root] = true;
  for (bool grew = true; grew;) {
    grew = false;
    for (const ChainPair<Pose>& p : pairs) {
      if (!p.joined || placed[p.first] == placed[p.second]) continue;
      if (placed[p.first]) {
        frame[p.second] = frame[p.first] * p.relative;
        placed[p.second] = true;
      } else {
        frame[p.first] = frame[p.second] * p.relative.inverse();
        placed[p.first] = true;
      }
      grew = true;
    }
  }
  return frame;
}

template <class Pose>
void MinimizeMaps(const PoseGraph<Pose>& graph,
                  const std::vector<int>& accepted, ChainMaps<Pose>* maps,
                  int only_map) {
  const int num_chains = static_cast<int>(maps->chains.size());
  DisjointSets joined(num_chains);
  for (const ChainPair<Pose>& p : maps->pairs) {
    if (p.joined) joined.Join(p.first, p.second);
  }
  maps->map_of_chain.resize(num_chains);
  for (int c = 0; c < num_chains; ++c) maps->map_of_chain[c] = joined.Find(c);
  maps->minimized.clear();
  for (int m = 0; m < num_chains; ++m) {
    if (only_map >= 0 && m != only_map) continue;
    std::vector<ChainSpan> spans;
    for (int c = 0; c < num_chains; ++c) {
      if (maps->map_of_chain[c] == m) spans.push_back(maps->chains[c]);
    }
    if (spans.empty()) continue;
    const std::vector<Pose> frame = FramesIn(maps->pairs, num_chains, m);
    std::vector<Pose> start = maps->estimates;
    for (int c = 0; c < num_chains; ++c) {
      if (maps->map_of_chain[c] != m) continue;
      for (int p = maps->chains[c].first; p <= maps->chains[c].last; ++p) {
        start[p] = frame[c] * maps->estimates[p];
      }
    }
    std::vector<int> loops;
    for (const int k : accepted) {
      const int chain = ChainHolding(maps->chains, graph.loops()[k].from);
      if (maps->map_of_chain[chain] == m) loops.push_back(k);
    }
    const PoseGraph<Pose> one = SubGraph(graph, spans, start, loops);
    const PoseGraphSolver<Pose> solver(one, 1);
    maps->minimized.emplace_back();
    const std::vector<Pose> map =
        solver.Optimize(AllLoops(one), ConvergenceOptions{},
                        &maps->minimized.back(), &one.estimates());
    const std::vector<int> poses = Poses(spans);
    for (size_t k = 0; k < poses.size(); ++k) {
      maps->estimates[poses[k]] = map[k];
    }
  }
}

template std::vector<Pose2> FramesIn(const std::vector<ChainPair<Pose2>>&, int,
                                     int);
template std::vector<Pose3> FramesIn(const std::vector<ChainPair<Pose3>>&, int,
                                     int);
template void MinimizeMaps(const PoseGraph<Pose2>&, const std::vector<int>&,
                           ChainMaps<Pose2>*, int);
template void MinimizeMaps(const PoseGraph<Pose3>&, const std::vector<int>&,
                           ChainMaps<Pose3>*, int);

}  // namespace rrr
