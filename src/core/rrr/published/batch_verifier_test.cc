// Batch RRR end to end on generated worlds whose answer is known.
#include "rrr/rrr/published/batch_verifier.h"

#include <gtest/gtest.h>

#include <set>

#include "rrr/geometry/pose2.h"
#include "rrr/sim/simulated_world.h"
#include "rrr/solver/pose_graph_solver.h"

namespace rrr {
namespace {

struct Outcome {
  int false_accepted = 0, true_accepted = 0, true_total = 0;
};

Outcome VerifyWorld(const WorldOptions& options) {
  const SimulatedWorld w = SimulateWorld(options);
  PoseGraphSolver<Pose2> solver(w.graph, 4);
  RrrOptions rrr;
  rrr.cluster_window = 10;
  const Verdict v = VerifyBatch(LoopEnds(w.graph), solver, rrr);
  EXPECT_EQ(v.accepted.size() + v.rejected.size(), w.graph.loops().size());
  const std::set<int> false_loops(w.false_loops.begin(), w.false_loops.end());
  Outcome o;
  o.true_total = static_cast<int>(w.graph.loops().size() - false_loops.size());
  for (const int k : v.accepted) {
    (false_loops.count(k) ? o.false_accepted : o.true_accepted)++;
  }
  return o;
}

TEST(VerifyBatch, RejectsRandomFalseLoopsAndKeepsTrueOnes) {
  WorldOptions options;
  options.poses = 1200;
  options.false_loops = 30;
  const Outcome o = VerifyWorld(options);
  EXPECT_EQ(o.false_accepted, 0);
  EXPECT_GT(o.true_accepted, o.true_total * 7 / 10);
}

TEST(VerifyBatch, RejectsGroupedFalseLoops) {
  WorldOptions options;
  options.poses = 1200;
  options.false_loops = 20;
  options.group = 5;
  options.seed = 4;
  const Outcome o = VerifyWorld(options);
  EXPECT_EQ(o.false_accepted, 0);
  EXPECT_GT(o.true_accepted, o.true_total / 2);
}

TEST(VerifyBatch, NoCandidatesIsTheOdometryChain) {
  WorldOptions options;
  options.poses = 200;
  options.false_loops = 0;
  options.loop_probability = 0;
  const SimulatedWorld w = SimulateWorld(options);
  ASSERT_TRUE(w.graph.loops().empty());
  PoseGraphSolver<Pose2> solver(w.graph, 4);
  const Verdict v = VerifyBatch(LoopEnds(w.graph), solver, RrrOptions());
  EXPECT_TRUE(v.accepted.empty());
  EXPECT_TRUE(v.clusters.empty());
  const auto map = solver.Optimize(v.accepted, {});
  EXPECT_LT(map.back().between(solver.initial().back()).Log().norm(), 1e-9);
}

TEST(VerifyBatch, DuplicateCandidatesAreBothJudged) {
  WorldOptions options;
  options.poses = 600;
  options.false_loops = 0;
  SimulatedWorld w = SimulateWorld(options);
  ASSERT_FALSE(w.graph.loops().empty());
  w.graph.AddEdge(w.graph.loops()[0]);  // a duplicate of the first loop
  PoseGraphSolver<Pose2> solver(w.graph, 4);
  RrrOptions rrr;
  const Verdict v = VerifyBatch(LoopEnds(w.graph), solver, rrr);
  const int last = static_cast<int>(w.graph.loops().size()) - 1;
  EXPECT_EQ(v.cluster_of_loop[0], v.cluster_of_loop[last]);
  const bool first = std::count(v.accepted.begin(), v.accepted.end(), 0) > 0;
  const bool dup = std::count(v.accepted.begin(), v.accepted.end(), last) > 0;
  EXPECT_EQ(first, dup);
}

TEST(VerifyBatch, ThreadsDoNotChangeTheDecisions) {
  WorldOptions options;
  options.poses = 1500;
  options.false_loops = 60;
  options.seed = 7;
  const SimulatedWorld w = SimulateWorld(options);
  PoseGraphSolver<Pose2> solver(w.graph, 4);
  RrrOptions rrr;
  const Verdict one = VerifyBatch(LoopEnds(w.graph), solver, rrr);
  ASSERT_FALSE(one.accepted.empty());
  ASSERT_FALSE(one.rejected.empty());
  for (const int threads : {2, 3}) {
    rrr.threads = threads;
    int reports = 0, last_done = 0;
    const Verdict many =
        VerifyBatch(LoopEnds(w.graph), solver, rrr, [&](int done, int total) {
          ++reports;
          EXPECT_EQ(done, last_done + 1);
          EXPECT_EQ(total, static_cast<int>(one.clusters.size()));
          last_done = done;
        });
    EXPECT_EQ(many.accepted, one.accepted) << threads << " threads";
    EXPECT_EQ(reports, static_cast<int>(one.clusters.size()));
  }
}

TEST(VerifyBatch, RejectsBadOptions) {
  WorldOptions options;
  options.poses = 200;
  const SimulatedWorld w = SimulateWorld(options);
  PoseGraphSolver<Pose2> solver(w.graph, 4);
  RrrOptions rrr;
  rrr.alpha = 1.5;
  EXPECT_THROW(VerifyBatch(LoopEnds(w.graph), solver, rrr),
               std::invalid_argument);
  rrr = RrrOptions();
  rrr.threads = 0;
  EXPECT_THROW(VerifyBatch(LoopEnds(w.graph), solver, rrr),
               std::invalid_argument);
}

}  // namespace
}  // namespace rrr
