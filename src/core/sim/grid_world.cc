#include "rrr/sim/grid_world.h"

#include <cmath>
#include <map>
#include <random>
#include <stdexcept>

#include "rrr/sim/false_loops.h"

namespace rrr {

std::string GridWorldOptions::Validate() const {
  if (poses < 100) return "poses must be at least 100";
  if (block < 2 || blocks < 2) return "block and blocks must be at least 2";
  if (translation_noise < 0 || rotation_noise < 0) return "noise must be >= 0";
  if (!(loop_probability >= 0 && loop_probability <= 1)) {
    return "loop_probability must be in [0, 1]";
  }
  if (min_gap < 2) return "min_gap must be at least 2";
  if (false_loops < 0 || group < 1)
    return "false loops must be >= 0, group >= 1";
  return "";
}

SimulatedWorld SimulateGridWorld(const GridWorldOptions& options) {
  const std::string problem = options.Validate();
  if (!problem.empty()) throw std::invalid_argument(problem);
  std::mt19937_64 rng(options.seed);
  std::normal_distribution<double> unit(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);

  // The true path: unit steps along streets, turning at random at crossings
  // and never leaving the city.
  const int size = options.block * options.blocks;
  int x = 0, y = 0, heading = 0;  // heading in quarter turns
  const int dx[4] = {1, 0, -1, 0}, dy[4] = {0, 1, 0, -1};
  SimulatedWorld world;
  world.truth.push_back(Pose2(0, 0, 0));
  std::map<std::pair<int, int>, std::vector<int>> visits{{{0, 0}, {0}}};
  std::vector<std::pair<int, int>> revisits;  // (earlier, later)
  for (int k = 1; k < options.poses; ++k) {
    if (x % options.block == 0 && y % options.block == 0) {
      const int turn = static_cast<int>(uniform(rng) * 3) - 1;  // -1, 0, 1
      heading = (heading + turn + 4) % 4;
      for (int tries = 0; tries < 4; ++tries) {
        const int nx = x + dx[heading], ny = y + dy[heading];
        if (nx >= 0 && nx <= size && ny >= 0 && ny <= size) break;
        heading = (heading + 1) % 4;
      }
    }
    x += dx[heading];
    y += dy[heading];
    world.truth.push_back(Pose2(x, y, heading * M_PI / 2));
    auto& seen = visits[{x, y}];
    for (auto it = seen.rbegin(); it != seen.rend(); ++it) {
      if (k - *it >= options.min_gap) {
        // The same place and heading (a loop detector matches views).
        if (std::abs(world.truth[*it].between(world.truth[k]).theta()) < 0.1 &&
            uniform(rng) < options.loop_probability) {
          revisits.emplace_back(*it, k);
        }
        break;
      }
    }
    seen.push_back(k);
  }

  // Odometry measurements with noise; vertex estimates compose them.
  Constraint<Pose2> edge;
  const double it =
      1.0 / (options.translation_noise * options.translation_noise + 1e-12);
  const double ir =
      1.0 / (options.rotation_noise * options.rotation_noise + 1e-12);
  edge.information = Eigen::Vector3d(it, it, ir).asDiagonal();
  const auto noisy = [&](const Pose2& z) {
    return z * Pose2(options.translation_noise * unit(rng),
                     options.translation_noise * unit(rng),
                     options.rotation_noise * unit(rng));
  };
  Pose2 estimate;
  world.graph.AddPose(0, estimate);
  std::vector<Constraint<Pose2>> odometry;
  for (int k = 1; k < options.poses; ++k) {
    edge.from = k - 1;
    edge.to = k;
    edge.measurement = noisy(world.truth[k - 1].between(world.truth[k]));
    estimate = estimate * edge.measurement;
    world.graph.AddPose(k, estimate);
    odometry.push_back(edge);
  }
  for (const auto& e : odometry) world.graph.AddEdge(e);
  for (const auto& [earlier, later] : revisits) {
    edge.from = later;
    edge.to = earlier;
    edge.measurement = noisy(world.truth[later].between(world.truth[earlier]));
    world.graph.AddEdge(edge);
  }

  FalseLoopOptions spoil;
  spoil.count = options.false_loops;
  spoil.group = options.group;
  spoil.seed = options.seed + 1;
  world.false_loops = AddFalseLoops(&world.graph, spoil, &world.truth);
  return world;
}

}  // namespace rrr
