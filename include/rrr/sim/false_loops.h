// Spoiling a pose graph with false loop closures (BENCHMARKS.md).
#ifndef RRR_SIM_FALSE_LOOPS_H_
#define RRR_SIM_FALSE_LOOPS_H_

#include <cstdint>
#include <string>
#include <vector>

#include "rrr/graph/pose_graph.h"

namespace rrr {

struct FalseLoopOptions {
  int count = 100;
  // Local: the second pose within `local_range` poses of the first.
  bool local = false;
  int local_range = 20;
  // Look-alike places (what a place recogniser reports for a similar view):
  // the poses at least `look_alike_gap` apart and a measurement near the
  // identity, its translation uniform in the ball of `look_alike_translation`
  // m and its rotation angle uniform up to `look_alike_rotation` rad (both 0:
  // the identity).
  bool look_alike = false;
  int look_alike_gap = 20;
  double look_alike_translation = 2.0;
  double look_alike_rotation = 0.5;
  // Groups of `group` consecutive false loops (i+k, j+k), k = 0..group-1,
  // sharing one drawn measurement, which look like a real revisit.
  int group = 1;
  // Between robots or sessions: both ends of every loop (and of its group's
  // links) in different odometry chains (ChainSpansOf); the graph needs two.
  bool between_chains = false;
  std::uint64_t seed = 1;

  // Empty if usable for a graph of `num_poses` poses, else the problem.
  std::string Validate(int num_poses) const;
};

// Adds `options.count` false loops between pose pairs drawn uniformly at
// random (|i - j| > 1), with a measurement drawn from x, y (, z) ~ N(0, 0.3 m)
// and each rotation angle ~ N(0, 10°) (or look-alike: see FalseLoopOptions),
// and the information matrix of the
// graph's first loop (of its first odometry edge if it has no loop). Returns
// the indices in graph->loops() of the added loops. No added loop shares its
// pair of poses with another loop of the graph (old or added), so lists of
// false loops by pose pair are exact. With `reference` (the true poses, or
// the optimum of the graph before, by pose index), a draw is discarded when
// one of its links would be correct there by kMetricRule (a measurement
// within 1 m and 15° of the pair's relative pose; on a revisited corner a
// local draw can be one): every added loop is false. `*discarded` (if given)
// is the number of such draws. The same seed (and reference) gives the same
// loops. Throws std::invalid_argument if the options do not validate, the
// reference has not one pose per graph pose, or free pairs are too rare to
// find.
template <class Pose>
std::vector<int> AddFalseLoops(PoseGraph<Pose>* graph,
                               const FalseLoopOptions& options,
                               const std::vector<Pose>* reference = nullptr,
                               int* discarded = nullptr);

}  // namespace rrr

#endif  // RRR_SIM_FALSE_LOOPS_H_
