#include "rrr/sim/false_loops.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <set>
#include <stdexcept>
#include <utility>

#include "rrr/eval/ground_truth.h"
#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/graph/chain_spans.h"

namespace rrr {
namespace {

constexpr double kTranslationSigma = 0.3;
constexpr double kAngleSigma = 10.0 * M_PI / 180.0;
// Draws per false loop before the graph is judged too full of loops.
constexpr int kMostDrawsPerLoop = 1000;

std::pair<int, int> PairOf(int a, int b) { return std::minmax(a, b); }

Pose2 RandomMeasurement(std::mt19937_64& rng, const Pose2*) {
  std::normal_distribution<double> t(0.0, kTranslationSigma),
      a(0.0, kAngleSigma);
  const double x = t(rng), y = t(rng);
  return Pose2(x, y, a(rng));
}

Pose3 RandomMeasurement(std::mt19937_64& rng, const Pose3*) {
  std::normal_distribution<double> t(0.0, kTranslationSigma),
      a(0.0, kAngleSigma);
  Eigen::Vector3d translation;
  for (int k = 0; k < 3; ++k) translation[k] = t(rng);
  const double roll = a(rng), pitch = a(rng), yaw = a(rng);
  const Eigen::Quaterniond q =
      Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
      Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
      Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX());
  return Pose3(q, translation);
}

// A unit vector of dimension D, uniformly distributed.
template <int D>
Eigen::Matrix<double, D, 1> RandomDirection(std::mt19937_64& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::Matrix<double, D, 1> v;
  do {
    for (int k = 0; k < D; ++k) v[k] = normal(rng);
  } while (v.norm() < 1e-9);
  return v.normalized();
}

// A look-alike measurement: the translation uniform in the ball of radius
// `translation`, the rotation angle uniform up to `rotation` about a random
// axis.
Pose2 LookAlikeMeasurement(std::mt19937_64& rng, double translation,
                           double rotation, const Pose2*) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const Eigen::Vector2d t =
      translation * std::sqrt(u(rng)) * RandomDirection<2>(rng);
  return Pose2(t.x(), t.y(), rotation * (2.0 * u(rng) - 1.0));
}

Pose3 LookAlikeMeasurement(std::mt19937_64& rng, double translation,
                           double rotation, const Pose3*) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const Eigen::Vector3d t =
      translation * std::cbrt(u(rng)) * RandomDirection<3>(rng);
  const Eigen::Vector3d axis = RandomDirection<3>(rng);
  return Pose3(Eigen::Quaterniond(Eigen::AngleAxisd(rotation * u(rng), axis)),
               t);
}

// Whether a link (i + k, j + k), k < `links`, with `measurement` is correct
// at the poses `truth` by kMetricRule.
template <class Pose>
bool AnyLinkCorrect(const std::vector<Pose>& truth, int i, int j, int links,
                    const Pose& measurement) {
  for (int k = 0; k < links; ++k) {
    if (JudgeLoop(measurement, truth[i + k], truth[j + k]).metric) return true;
  }
  return false;
}

}  // namespace

std::string FalseLoopOptions::Validate(int num_poses) const {
  if (count < 0) return "the number of false loops must not be negative";
  if (group < 1) return "the group size must be at least 1";
  if (local_range < 2) return "the local range must be at least 2";
  if (local && look_alike) return "false loops are local or look-alike";
  if (look_alike_gap < 2) return "the look-alike gap must be at least 2";
  if (!(look_alike_translation >= 0 && look_alike_rotation >= 0)) {
    return "the look-alike bounds must not be negative";
  }
  if (num_poses < group + 3) {
    return "the graph has too few poses (" + std::to_string(num_poses) +
           ") for groups of " + std::to_string(group);
  }
  return "";
}

template <class Pose>
std::vector<int> AddFalseLoops(PoseGraph<Pose>* graph,
                               const FalseLoopOptions& options,
                               const std::vector<Pose>* reference,
                               int* discarded) {
  const int n = graph->num_poses();
  const std::string problem = options.Validate(n);
  if (!problem.empty()) throw std::invalid_argument(problem);
  if (reference && static_cast<int>(reference->size()) != n) {
    throw std::invalid_argument("the reference has " +
                                std::to_string(reference->size()) +
                                " poses, the graph " + std::to_string(n));
  }
  const std::vector<ChainSpan> chains = ChainSpansOf(*graph);
  if (options.between_chains && chains.size() < 2) {
    throw std::invalid_argument(
        "false loops between chains need a graph of two chains or more");
  }
  // Whether the links from (i, j) on stay each in one chain, and, between
  // chains, join two.
  const auto chains_fit = [&](int i, int j, int links) {
    const int a = ChainHolding(chains, i), b = ChainHolding(chains, j);
    return a == ChainHolding(chains, i + links - 1) &&
           b == ChainHolding(chains, j + links - 1) &&
           (!options.between_chains || a != b);
  };
  int correct_draws = 0;
  const auto information = graph->loops().empty()
                               ? graph->odometry().at(0).information
                               : graph->loops().front().information;
  std::mt19937_64 rng(options.seed);
  // The first pose of a group leaves room for the group's other members.
  const int last_start = n - options.group;
  std::uniform_int_distribution<int> any(0, last_start - 1);
  std::uniform_int_distribution<int> offset(-options.local_range,
                                            options.local_range);
  // Pose pairs that hold a loop: a false loop never shares one, so that a
  // candidate's pair names it alone (false-loop lists are lists of pairs).
  std::set<std::pair<int, int>> taken;
  for (const auto& loop : graph->loops())
    taken.insert(PairOf(loop.from, loop.to));
  const auto group_fits = [&](int i, int j) {
    for (int k = 0; k < options.group; ++k) {
      if (taken.count(PairOf(i + k, j + k))) return false;
    }
    return true;
  };
  std::vector<int> added;
  const std::int64_t most_draws =
      std::int64_t{kMostDrawsPerLoop} * options.count;
  std::int64_t draws = 0;
  while (static_cast<int>(added.size()) < options.count) {
    if (++draws > most_draws) {
      throw std::invalid_argument("found no free pose pair for false loop " +
                                  std::to_string(added.size() + 1) + " of " +
                                  std::to_string(options.count) + " in " +
                                  std::to_string(most_draws) + " draws (" +
                                  std::to_string(correct_draws) +
                                  " discarded as correct loops)");
    }
    const int i = any(rng);
    const int j = options.local ? i + offset(rng) : any(rng);
    if (j < 0 || j >= last_start || std::abs(i - j) <= 1) continue;
    if (options.look_alike && std::abs(i - j) < options.look_alike_gap) {
      continue;
    }
    if (!group_fits(i, j)) continue;
    const int links =
        std::min(options.group, options.count - static_cast<int>(added.size()));
    if (!chains_fit(i, j, links)) continue;
    // One measurement for the whole group: its links agree with each other
    // like a real revisit's.
    const Pose* kind = nullptr;
    const Pose measurement =
        options.look_alike
            ? LookAlikeMeasurement(rng, options.look_alike_translation,
                                   options.look_alike_rotation, kind)
            : RandomMeasurement(rng, kind);
    if (reference && AnyLinkCorrect(*reference, i, j, links, measurement)) {
      ++correct_draws;
      continue;
    }
    for (int k = 0; k < links; ++k) {
      Constraint<Pose> loop;
      loop.from = i + k;
      loop.to = j + k;
      loop.measurement = measurement;
      loop.information = information;
      graph->AddEdge(loop);
      taken.insert(PairOf(loop.from, loop.to));
      added.push_back(static_cast<int>(graph->loops().size()) - 1);
    }
  }
  if (discarded) *discarded = correct_draws;
  return added;
}

template std::vector<int> AddFalseLoops(PoseGraph<Pose2>*,
                                        const FalseLoopOptions&,
                                        const std::vector<Pose2>*, int*);
template std::vector<int> AddFalseLoops(PoseGraph<Pose3>*,
                                        const FalseLoopOptions&,
                                        const std::vector<Pose3>*, int*);

}  // namespace rrr
