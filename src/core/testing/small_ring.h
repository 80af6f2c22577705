// A small ring world whose map procedure's state, saved part way, holds
// clusters accepted, refused and pending: for the state's tests and the
// map_state fuzz target.
#ifndef RRR_CORE_TESTING_SMALL_RING_H_
#define RRR_CORE_TESTING_SMALL_RING_H_

#include "rrr/sim/simulated_world.h"

namespace rrr::testing {

// Where the state is saved: by this pose index clusters are accepted,
// refused and pending.
constexpr int kSmallRingSavedPoses = 150;

// Five laps of a ring of 40 poses (85 true loops) with 10 false loops in
// groups of 2, made once.
inline const SimulatedWorld& SmallRing() {
  static const SimulatedWorld world = [] {
    WorldOptions options;
    options.layout = Layout::kRing;
    options.ring = 40;
    options.poses = 200;
    options.false_loops = 10;
    options.group = 2;
    return SimulateWorld(options);
  }();
  return world;
}

}  // namespace rrr::testing

#endif  // RRR_CORE_TESTING_SMALL_RING_H_
