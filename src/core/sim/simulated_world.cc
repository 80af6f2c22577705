#include "rrr/sim/simulated_world.h"

#include <cmath>
#include <map>
#include <random>
#include <stdexcept>

#include "rrr/sim/false_loops.h"

namespace rrr {
namespace {

// A place: what a loop detector recognizes (a grid crossing or street
// point, a point of the ring, a point of the road).
using Place = std::pair<int, int>;

// Drives one step of 1 m at a time, from the origin heading along x.
class Driver {
 public:
  Driver(const WorldOptions& options, std::mt19937_64* rng)
      : options_(options), rng_(rng) {}

  // The true pose and the place after `k` steps; draws from the generator
  // only on the grid (to turn at crossings).
  std::pair<Pose2, Place> Step(int k) {
    switch (options_.layout) {
      case Layout::kGrid:
        return GridStep();
      case Layout::kRing: {
        const double turn = 2 * M_PI / options_.ring;
        const double radius = 0.5 / std::sin(turn / 2);  // chords of 1 m
        const double a = turn * k;
        return {Pose2(radius * std::sin(a), radius * (1 - std::cos(a)), a),
                {k % options_.ring, 0}};
      }
      case Layout::kLine:
        break;
    }
    return {Pose2(k, 0, 0), {k, 0}};
  }

 private:
  // Unit steps along streets, turning at random at crossings and never
  // leaving the city.
  std::pair<Pose2, Place> GridStep() {
    const int size = options_.block * options_.blocks;
    const int dx[4] = {1, 0, -1, 0}, dy[4] = {0, 1, 0, -1};
    if (x_ % options_.block == 0 && y_ % options_.block == 0) {
      const int turn = static_cast<int>(uniform_(*rng_) * 3) - 1;  // -1, 0, 1
      heading_ = (heading_ + turn + 4) % 4;
      for (int tries = 0; tries < 4; ++tries) {
        const int nx = x_ + dx[heading_], ny = y_ + dy[heading_];
        if (nx >= 0 && nx <= size && ny >= 0 && ny <= size) break;
        heading_ = (heading_ + 1) % 4;
      }
    }
    x_ += dx[heading_];
    y_ += dy[heading_];
    return {Pose2(x_, y_, heading_ * M_PI / 2), {x_, y_}};
  }

  const WorldOptions& options_;
  std::mt19937_64* rng_;
  std::uniform_real_distribution<double> uniform_{0.0, 1.0};
  int x_ = 0, y_ = 0, heading_ = 0;  // heading in quarter turns
};

}  // namespace

const char* ToString(Layout layout) {
  switch (layout) {
    case Layout::kRing:
      return "ring";
    case Layout::kLine:
      return "line";
    default:
      return "grid";
  }
}

bool ParseLayout(const std::string& name, Layout* layout) {
  for (const Layout l : {Layout::kGrid, Layout::kRing, Layout::kLine}) {
    if (name == ToString(l)) {
      *layout = l;
      return true;
    }
  }
  return false;
}

std::string WorldOptions::Validate() const {
  if (poses < 100) return "poses must be at least 100";
  if (block < 2 || blocks < 2) return "block and blocks must be at least 2";
  if (ring < 20) return "ring must be at least 20";
  if (translation_noise < 0 || rotation_noise < 0) return "noise must be >= 0";
  if (!(loop_probability >= 0 && loop_probability <= 1)) {
    return "loop_probability must be in [0, 1]";
  }
  if (min_gap < 2) return "min_gap must be at least 2";
  if (loops_per_revisit < 1) return "loops_per_revisit must be at least 1";
  if (false_loops < 0 || group < 1)
    return "false loops must be >= 0, group >= 1";
  if (robots < 1 || robots > 26 || poses / robots < 100) {
    return "robots must be 1 to 26, with at least 100 poses each";
  }
  return "";
}

SimulatedWorld SimulateWorld(const WorldOptions& options) {
  const std::string problem = options.Validate();
  if (!problem.empty()) throw std::invalid_argument(problem);
  std::mt19937_64 rng(options.seed);
  std::normal_distribution<double> unit(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);

  // The true path. A revisit of a place seen at least min_gap poses
  // before, with the same heading (a loop detector matches views), yields a
  // true loop candidate with loop_probability, with each of up to
  // loops_per_revisit such visits, the latest first.
  SimulatedWorld world;
  Driver driver(options, &rng);
  world.truth.push_back(Pose2(0, 0, 0));
  std::map<Place, std::vector<int>> visits{{{0, 0}, {0}}};
  std::vector<std::pair<int, int>> revisits;  // (earlier, later)
  for (int k = 1; k < options.poses; ++k) {
    const auto [pose, place] = driver.Step(k);
    world.truth.push_back(pose);
    auto& seen = visits[place];
    int matched = 0;
    for (auto it = seen.rbegin();
         it != seen.rend() && matched < options.loops_per_revisit; ++it) {
      if (k - *it < options.min_gap) continue;
      ++matched;
      if (std::abs(world.truth[*it].between(world.truth[k]).theta()) < 0.1 &&
          uniform(rng) < options.loop_probability) {
        revisits.emplace_back(*it, k);
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
  // Robot r drives poses [first(r), first(r + 1)).
  const auto first = [&](int r) {
    return static_cast<int>(std::int64_t{options.poses} * r / options.robots);
  };
  Pose2 estimate;
  std::vector<Constraint<Pose2>> odometry;
  for (int r = 0, k = 0; r < options.robots; ++r) {
    const PoseId base =
        options.robots == 1 ? 0 : PoseId{'a' + r} << 56;  // AsSymbol
    for (; k < first(r + 1); ++k) {
      if (k == first(r)) {
        estimate = Pose2();  // a robot's odometry starts at the identity
      } else {
        edge.from = k - 1;
        edge.to = k;
        edge.measurement = noisy(world.truth[k - 1].between(world.truth[k]));
        estimate = estimate * edge.measurement;
        odometry.push_back(edge);
      }
      world.graph.AddPose(base + k - first(r), estimate);
    }
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
