// A built-in synthetic world: a robot driving the streets of a grid city.
#ifndef RRR_SIM_GRID_WORLD_H_
#define RRR_SIM_GRID_WORLD_H_

#include <cstdint>
#include <string>
#include <vector>

#include "rrr/geometry/pose2.h"
#include "rrr/graph/pose_graph.h"

namespace rrr {

struct GridWorldOptions {
  int poses = 3000;
  // Streets every `block` steps of 1 m; the city is `blocks` × `blocks`.
  int block = 8;
  int blocks = 6;
  // Odometry noise per step (standard deviations, m and rad).
  double translation_noise = 0.02;
  double rotation_noise = 0.005;
  // Chance that a revisit of a place seen at least `min_gap` poses ago
  // yields a (true) loop candidate, and the noise of its measurement.
  double loop_probability = 0.5;
  int min_gap = 30;
  // False loops, drawn as `rrr spoil` draws them (each wrong at the true
  // poses), in groups of `group`.
  int false_loops = 40;
  int group = 1;
  std::uint64_t seed = 1;

  // Empty if usable, else the problem.
  std::string Validate() const;
};

struct SimulatedWorld {
  PoseGraph<Pose2> graph;        // odometry chain as the vertex estimates
  std::vector<Pose2> truth;      // the true poses
  std::vector<int> false_loops;  // indices into graph.loops()
};

// Simulates the world. Same options, same world. Throws
// std::invalid_argument if the options do not validate.
SimulatedWorld SimulateGridWorld(const GridWorldOptions& options);

}  // namespace rrr

#endif  // RRR_SIM_GRID_WORLD_H_
