// Built-in synthetic worlds: a robot driving the streets of a grid city,
// around a ring, or along a straight road.
#ifndef RRR_SIM_SIMULATED_WORLD_H_
#define RRR_SIM_SIMULATED_WORLD_H_

#include <cstdint>
#include <string>
#include <vector>

#include "rrr/geometry/pose2.h"
#include "rrr/graph/pose_graph.h"

namespace rrr {

// Where the robot drives, in steps of 1 m.
enum class Layout {
  // The streets of a grid city, turning at random at crossings: revisits
  // everywhere.
  kGrid,
  // Around a circle of `ring` poses and on past its start: every revisit
  // closes the one place where the laps overlap.
  kRing,
  // Straight on: no place is seen twice, so every loop candidate is false.
  kLine,
};
const char* ToString(Layout layout);
// Parses "grid", "ring" or "line"; returns false for anything else.
bool ParseLayout(const std::string& name, Layout* layout);

struct WorldOptions {
  Layout layout = Layout::kGrid;
  int poses = 3000;
  // Grid: streets every `block` steps; the city is `blocks` × `blocks`.
  int block = 8;
  int blocks = 6;
  // Ring: poses per lap.
  int ring = 200;
  // Odometry noise per step (standard deviations, m and rad).
  double translation_noise = 0.02;
  double rotation_noise = 0.005;
  // Chance that a revisit of a place seen at least `min_gap` poses ago
  // yields a (true) loop candidate, and the noise of its measurement.
  double loop_probability = 0.5;
  int min_gap = 30;
  // A revisit is matched with up to this many earlier visits of the place
  // (the latest first), each a candidate with loop_probability.
  int loops_per_revisit = 1;
  // False loops, drawn as `rrr spoil` draws them (each wrong at the true
  // poses), in groups of `group`.
  int false_loops = 40;
  int group = 1;
  // Robots that drive the path in turn, poses / robots each: each an
  // odometry chain of its own that starts at the identity (no odometry
  // between robots; only loops join them), its poses keyed as the GTSAM
  // symbols 'a', 'b', ... when there are several (AsSymbol).
  int robots = 1;
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
SimulatedWorld SimulateWorld(const WorldOptions& options);

}  // namespace rrr

#endif  // RRR_SIM_SIMULATED_WORLD_H_
