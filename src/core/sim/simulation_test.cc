// The false-loop generator and the grid world.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <utility>

#include "rrr/eval/ground_truth.h"
#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/graph/chain_spans.h"
#include "rrr/io/symbol_key.h"
#include "rrr/sim/false_loops.h"
#include "rrr/sim/simulated_world.h"

namespace rrr {
namespace {

PoseGraph<Pose2> Chain(int n) {
  PoseGraph<Pose2> g;
  for (int k = 0; k < n; ++k) g.AddPose(k, Pose2(k, 0, 0));
  Constraint<Pose2> e;
  for (int k = 0; k + 1 < n; ++k) {
    e.from = k;
    e.to = k + 1;
    e.measurement = Pose2(1, 0, 0);
    g.AddEdge(e);
  }
  return g;
}

TEST(AddFalseLoops, AddsNonOdometryLoopsReproducibly) {
  auto a = Chain(200), b = Chain(200);
  FalseLoopOptions options;
  options.count = 50;
  options.seed = 9;
  const auto added = AddFalseLoops(&a, options);
  AddFalseLoops(&b, options);
  ASSERT_EQ(added.size(), 50u);
  ASSERT_EQ(a.loops().size(), 50u);
  for (size_t k = 0; k < a.loops().size(); ++k) {
    EXPECT_GT(std::abs(a.loops()[k].from - a.loops()[k].to), 1);
    EXPECT_EQ(a.loops()[k].from, b.loops()[k].from);
    EXPECT_EQ(a.loops()[k].measurement.x(), b.loops()[k].measurement.x());
  }
  EXPECT_TRUE(a.odometry().size() == 199u);
}

TEST(AddFalseLoops, LookAlikeLoopsJoinDistantPosesWithANearIdentity) {
  auto g = Chain(300);
  FalseLoopOptions options;
  options.count = 60;
  options.look_alike = true;
  AddFalseLoops(&g, options);
  ASSERT_EQ(g.loops().size(), 60u);
  for (const auto& loop : g.loops()) {
    EXPECT_GE(std::abs(loop.from - loop.to), options.look_alike_gap);
    EXPECT_LE(loop.measurement.translation().norm(), 2.0);
    EXPECT_LE(std::abs(loop.measurement.theta()), 0.5);
  }
  // Bounds of zero: the identity, what a junk stream reports.
  auto junk = Chain(300);
  options.look_alike_translation = options.look_alike_rotation = 0.0;
  AddFalseLoops(&junk, options);
  for (const auto& loop : junk.loops()) {
    EXPECT_EQ(loop.measurement.Log().norm(), 0.0);
  }
  options.local = true;
  EXPECT_THROW(AddFalseLoops(&junk, options), std::invalid_argument);
}

TEST(SimulateWorld, TheRingClosesOnePlaceAndTheLineNone) {
  WorldOptions options;
  options.layout = Layout::kRing;
  options.ring = 200;
  options.poses = 300;
  options.false_loops = 0;
  const SimulatedWorld ring = SimulateWorld(options);
  ASSERT_GT(ring.graph.loops().size(), 20u);
  for (const auto& loop : ring.graph.loops()) {
    // Every revisit: a pose of the second lap and the same point of the
    // first, where the true poses coincide.
    EXPECT_EQ(std::abs(loop.from - loop.to), options.ring);
    EXPECT_LT(ring.truth[loop.from].between(ring.truth[loop.to]).Log().norm(),
              1e-9);
  }
  options.layout = Layout::kLine;
  EXPECT_TRUE(SimulateWorld(options).graph.loops().empty());
  Layout parsed;
  EXPECT_TRUE(ParseLayout("ring", &parsed));
  EXPECT_EQ(parsed, Layout::kRing);
  EXPECT_FALSE(ParseLayout("circle", &parsed));
}

TEST(AddFalseLoops, LocalAndGroupedVariants) {
  auto g = Chain(300);
  FalseLoopOptions options;
  options.count = 40;
  options.local = true;
  options.group = 4;
  const auto added = AddFalseLoops(&g, options);
  ASSERT_EQ(added.size(), 40u);
  for (size_t k = 0; k < added.size(); ++k) {
    const auto& loop = g.loops()[added[k]];
    EXPECT_LE(std::abs(loop.from - loop.to), 20);
    if (k % 4 != 0) {  // consecutive within a group
      EXPECT_EQ(loop.from, g.loops()[added[k - 1]].from + 1);
      EXPECT_EQ(loop.to, g.loops()[added[k - 1]].to + 1);
    }
  }
}

TEST(AddFalseLoops, NeverSharesAPairOfPosesWithAnotherLoop) {
  // Loops on every pair 2..4 poses apart except (10, 13) and (12, 14): local
  // false loops within 4 poses have these two pairs left.
  auto g = Chain(30);
  Constraint<Pose2> loop;
  for (int i = 0; i < 30; ++i) {
    for (int j = i + 2; j <= std::min(i + 4, 29); ++j) {
      if ((i == 10 && j == 13) || (i == 12 && j == 14)) continue;
      loop.from = i;
      loop.to = j;
      g.AddEdge(loop);
    }
  }
  const size_t true_loops = g.loops().size();
  FalseLoopOptions options;
  options.local = true;
  options.local_range = 4;
  options.count = 2;
  auto spoiled = g;
  const auto added = AddFalseLoops(&spoiled, options);
  ASSERT_EQ(added.size(), 2u);
  std::set<std::pair<int, int>> pairs;
  for (const int k : added) {
    const auto& e = spoiled.loops()[k];
    pairs.insert(std::minmax(e.from, e.to));
  }
  EXPECT_EQ(pairs, (std::set<std::pair<int, int>>{{10, 13}, {12, 14}}));
  EXPECT_EQ(spoiled.loops().size(), true_loops + 2);
  // A third has no free pair: a clear error, not an endless draw.
  options.count = 3;
  auto full = g;
  EXPECT_THROW(AddFalseLoops(&full, options), std::invalid_argument);
}

TEST(AddFalseLoops, WithAReferenceEveryLoopIsWrongThere) {
  // A robot that goes back and forth over 0.5 m: nearby poses 2..4 apart
  // are nearly in one place, where a drawn measurement is often right.
  PoseGraph<Pose2> g;
  std::vector<Pose2> truth;
  for (int k = 0; k < 300; ++k) {
    truth.emplace_back(0.25 * (k % 3), 0.0, 0.0);
    g.AddPose(k, truth.back());
  }
  Constraint<Pose2> e;
  for (int k = 0; k + 1 < 300; ++k) {
    e.from = k;
    e.to = k + 1;
    e.measurement = truth[k].between(truth[k + 1]);
    g.AddEdge(e);
  }
  FalseLoopOptions options;
  options.count = 60;
  options.local = true;
  options.local_range = 4;
  options.group = 2;
  const auto correct_ones = [&](const PoseGraph<Pose2>& spoiled,
                                const std::vector<int>& added) {
    int correct = 0;
    for (const int k : added) {
      const auto& l = spoiled.loops()[k];
      correct += JudgeLoop(l.measurement, truth[l.from], truth[l.to]).metric;
    }
    return correct;
  };
  auto unchecked = g;
  EXPECT_GT(correct_ones(unchecked, AddFalseLoops(&unchecked, options)), 10);
  auto checked = g;
  int discarded = -1;
  const auto added = AddFalseLoops(&checked, options, &truth, &discarded);
  EXPECT_EQ(added.size(), 60u);
  EXPECT_EQ(correct_ones(checked, added), 0);
  EXPECT_GT(discarded, 5);
  // The same seed and reference, the same loops.
  auto again = g;
  AddFalseLoops(&again, options, &truth);
  for (const int k : added) {
    EXPECT_EQ(again.loops()[k].from, checked.loops()[k].from);
    EXPECT_EQ(again.loops()[k].measurement.x(),
              checked.loops()[k].measurement.x());
  }
  // A reference of another length is an error.
  truth.pop_back();
  EXPECT_THROW(AddFalseLoops(&again, options, &truth), std::invalid_argument);
}

TEST(AddFalseLoops, Works3DAndRejectsBadOptions) {
  PoseGraph<Pose3> g;
  for (int k = 0; k < 50; ++k) g.AddPose(k, Pose3());
  Constraint<Pose3> e;
  for (int k = 0; k + 1 < 50; ++k) {
    e.from = k;
    e.to = k + 1;
    g.AddEdge(e);
  }
  FalseLoopOptions options;
  options.count = 10;
  EXPECT_EQ(AddFalseLoops(&g, options).size(), 10u);
  options.group = 0;
  EXPECT_THROW(AddFalseLoops(&g, options), std::invalid_argument);
}

TEST(SimulateWorld, OdometryIsNoisyTruthAndLoopsAreTrue) {
  WorldOptions options;
  options.poses = 600;
  options.false_loops = 10;
  const SimulatedWorld w = SimulateWorld(options);
  EXPECT_EQ(w.graph.num_poses(), 600);
  EXPECT_EQ(w.graph.CheckChain(), "");
  EXPECT_EQ(w.false_loops.size(), 10u);
  ASSERT_GT(w.graph.loops().size(), 20u);
  // True loops measure the true relative pose up to odometry-sized noise.
  for (size_t k = 0; k < w.graph.loops().size() - 10; ++k) {
    const auto& l = w.graph.loops()[k];
    const Pose2 err =
        w.truth[l.from].between(w.truth[l.to]).between(l.measurement);
    EXPECT_LT(err.translation().norm(), 0.2);
  }
  EXPECT_EQ(SimulateWorld(options).graph.loops()[3].from,
            w.graph.loops()[3].from);
}

TEST(SimulateWorld, RobotsDriveInTurnEachItsOwnChainKeyedByItsLetter) {
  WorldOptions options;
  options.poses = 900;
  options.robots = 3;
  options.false_loops = 0;
  const SimulatedWorld world = SimulateWorld(options);
  const std::vector<ChainSpan> chains = ChainSpansOf(world.graph);
  ASSERT_EQ(chains.size(), 3u);
  for (int r = 0; r < 3; ++r) {
    EXPECT_EQ(chains[r].size(), 300);
    const auto symbol = AsSymbol(world.graph.ids()[chains[r].first]);
    ASSERT_TRUE(symbol.has_value());
    EXPECT_EQ(symbol->robot, 'a' + r);
    EXPECT_EQ(symbol->index, 0);
    // Each robot's odometry starts at the identity.
    EXPECT_EQ(world.graph.estimates()[chains[r].first].translation().norm(),
              0.0);
  }
  int between = 0;
  for (const auto& e : world.graph.loops()) {
    between += ChainHolding(chains, e.from) != ChainHolding(chains, e.to);
  }
  EXPECT_GT(between, 0);
  options.robots = 10;  // 90 poses each
  EXPECT_THROW(SimulateWorld(options), std::invalid_argument);
}

}  // namespace
}  // namespace rrr
