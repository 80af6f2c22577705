// The comparison methods (DCS, GNC-TLS, PCM) on generated worlds: each
// separates most false loops from the true ones, and each reacts to a single
// gross outlier as its rule says. DCS and GNC start from the odometry and
// only reach the true loops when their initial errors are moderate (a
// property of the methods, which RRR's clustering and trials do not share),
// so the worlds here have exact odometry and noisy loops.
#include <gtest/gtest.h>

#include <functional>
#include <set>

#include "rrr/geometry/pose2.h"
#include "rrr/robust/dcs.h"
#include "rrr/robust/gnc_tls.h"
#include "rrr/robust/pcm.h"
#include "rrr/sim/false_loops.h"
#include "rrr/sim/simulated_world.h"

namespace rrr {
namespace {

using Method = std::function<Verdict(const PoseGraph<Pose2>&)>;

struct Named {
  const char* name;
  Method verify;
};

// A grid world whose odometry is the true motion (its information as
// generated), with its noisy true loops and `false_loops` false ones.
SimulatedWorld ExactOdometryWorld(int poses, int false_loops) {
  WorldOptions options;
  options.poses = poses;
  options.false_loops = false_loops;
  SimulatedWorld world = SimulateWorld(options);
  PoseGraph<Pose2> exact;
  for (int p = 0; p < world.graph.num_poses(); ++p) {
    exact.AddPose(world.graph.ids()[p], world.truth[p]);
  }
  for (Constraint<Pose2> e : world.graph.odometry()) {
    e.measurement = world.truth[e.from].between(world.truth[e.to]);
    exact.AddEdge(e);
  }
  for (const auto& e : world.graph.loops()) exact.AddEdge(e);
  world.graph = exact;
  return world;
}

std::vector<Named> Methods() {
  return {
      {"dcs", [](const auto& g) { return VerifyWithDcs(g, DcsOptions()); }},
      {"gnc",
       [](const auto& g) { return VerifyWithGncTls(g, GncTlsOptions()); }},
      {"pcm", [](const auto& g) { return VerifyWithPcm(g, PcmOptions()); }},
  };
}

TEST(RobustMethods, SeparateFalseLoopsFromTrueOnes) {
  const SimulatedWorld world = ExactOdometryWorld(1200, 30);
  const std::set<int> false_loops(world.false_loops.begin(),
                                  world.false_loops.end());
  const int true_loops =
      static_cast<int>(world.graph.loops().size() - false_loops.size());
  for (const Named& method : Methods()) {
    const Verdict verdict = method.verify(world.graph);
    int false_accepted = 0;
    for (const int k : verdict.accepted) false_accepted += false_loops.count(k);
    const int true_accepted =
        static_cast<int>(verdict.accepted.size()) - false_accepted;
    EXPECT_LE(false_accepted, 1) << method.name;
    EXPECT_GE(true_accepted, 0.85 * true_loops) << method.name;
    EXPECT_EQ(verdict.accepted.size() + verdict.rejected.size(),
              world.graph.loops().size())
        << method.name;
  }
}

TEST(RobustMethods, RejectAGrossOutlierAndKeepTheRest) {
  SimulatedWorld world = ExactOdometryWorld(600, 0);
  const int loops = static_cast<int>(world.graph.loops().size());
  ASSERT_GT(loops, 5);
  // One candidate that claims the far end of a revisit is 8 m away.
  Constraint<Pose2> outlier = world.graph.loops()[loops / 2];
  outlier.measurement = outlier.measurement * Pose2(8.0, -3.0, 1.5);
  world.graph.AddEdge(outlier);
  for (const Named& method : Methods()) {
    const Verdict verdict = method.verify(world.graph);
    EXPECT_EQ(verdict.rejected.size() > 0 ? verdict.rejected.back() : -1, loops)
        << method.name;
    EXPECT_GE(static_cast<double>(verdict.accepted.size()), 0.85 * loops)
        << method.name;
  }
}

TEST(RobustMethods, PcmJoinsTwoRobotsByTheLoopsBetweenThem) {
  // Two robots that drive one city in turn, each an odometry chain from the
  // identity, and 30 false loops between them. PCM's inter-robot test closes
  // each cycle of two loops between the robots with the odometry of both;
  // there is no odometry between the chains to compare them with.
  WorldOptions options;
  options.poses = 1200;
  options.robots = 2;
  options.false_loops = 0;
  SimulatedWorld world = SimulateWorld(options);
  FalseLoopOptions spoil;
  spoil.count = 30;
  spoil.between_chains = true;
  const std::vector<int> added = AddFalseLoops(&world.graph, spoil);
  const std::set<int> false_loops(added.begin(), added.end());
  ChainMaps<Pose2> maps;
  const Verdict verdict = VerifyWithPcm(world.graph, PcmOptions(), &maps);
  ASSERT_EQ(maps.chains.size(), 2u);
  ASSERT_EQ(maps.pairs.size(), 1u);
  const int second = maps.chains[1].first;
  int true_between = 0, true_kept = 0, false_kept = 0;
  for (const int k : maps.pairs[0].candidates) {
    const bool kept = std::binary_search(maps.pairs[0].accepted.begin(),
                                         maps.pairs[0].accepted.end(), k);
    if (false_loops.count(k)) {
      false_kept += kept;
    } else {
      ++true_between;
      true_kept += kept;
    }
  }
  ASSERT_GT(true_between, 5);
  EXPECT_LE(false_kept, 1);
  EXPECT_GE(true_kept, 0.85 * true_between);
  EXPECT_EQ(verdict.accepted.size() + verdict.rejected.size(),
            world.graph.loops().size());
  // Joined into one map, the second robot where it really started.
  EXPECT_TRUE(maps.pairs[0].joined);
  EXPECT_EQ(maps.map_of_chain, (std::vector<int>{0, 0}));
  const Pose2 start = maps.estimates[0].between(maps.estimates[second]);
  const Pose2 truth = world.truth[0].between(world.truth[second]);
  EXPECT_LT((start.translation() - truth.translation()).norm(), 1.0);
}

}  // namespace
}  // namespace rrr
