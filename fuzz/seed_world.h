// The small generated world of the g2o and session seeds
// (fuzz/make_seeds.cc).
#ifndef RRR_FUZZ_SEED_WORLD_H_
#define RRR_FUZZ_SEED_WORLD_H_

#include "rrr/graph/pose_graph.h"
#include "rrr/sim/simulated_world.h"

namespace rrr_fuzz {

// A grid of 120 poses with 6 false loops in groups of 2, made once.
inline const rrr::PoseGraph<rrr::Pose2>& SeedWorld() {
  static const rrr::SimulatedWorld world = [] {
    rrr::WorldOptions options;
    options.poses = 120;
    options.false_loops = 6;
    options.group = 2;
    return rrr::SimulateWorld(options);
  }();
  return world.graph;
}

}  // namespace rrr_fuzz

#endif  // RRR_FUZZ_SEED_WORLD_H_
