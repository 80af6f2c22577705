// Incremental RRR: waiting candidates, and equality with batch at the end.
#include "rrr/rrr/published/incremental_verifier.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <set>

#include "../../testing/dataset_dir.h"
#include "../../testing/replay.h"
#include "rrr/geometry/pose2.h"
#include "rrr/io/g2o.h"
#include "rrr/rrr/published/batch_verifier.h"
#include "rrr/sim/simulated_world.h"
#include "rrr/solver/pose_graph_solver.h"

namespace rrr {
namespace {

using testing::Pairs;
using Replay = testing::Replay<IncrementalVerifier<Pose2>, Pose2>;

Pairs BatchAccepted(const PoseGraph<Pose2>& graph, const RrrOptions& options) {
  PoseGraphSolver<Pose2> solver(graph, options.iterations);
  const Verdict v = VerifyBatch(LoopEnds(graph), solver, options);
  Pairs out;
  for (const int k : v.accepted) {
    out.insert(
        {graph.ids()[graph.loops()[k].from], graph.ids()[graph.loops()[k].to]});
  }
  return out;
}

TEST(IncrementalVerifier, EndsWithTheBatchDecisionsOnASpoiledWorld) {
  WorldOptions world;
  world.poses = 1500;
  world.false_loops = 40;
  world.group = 4;
  const SimulatedWorld w = SimulateWorld(world);
  RrrOptions options;
  const Replay replay(w.graph, options);
  EXPECT_EQ(replay.verifier.num_waiting(), 0);
  for (int c = 0; c < replay.verifier.num_candidates(); ++c) {
    EXPECT_NE(replay.verifier.state(c), LoopState::kPending);
  }
  const Pairs batch = BatchAccepted(w.graph, options);
  EXPECT_FALSE(batch.empty());
  EXPECT_EQ(replay.Accepted(), batch);
  // Decisions were made along the way, not only at the end.
  EXPECT_GT(replay.verifier.num_solves(), 0);

  // Solving on two threads changes nothing.
  RrrOptions threaded = options;
  threaded.threads = 2;
  const Replay threaded_replay(w.graph, threaded);
  EXPECT_EQ(threaded_replay.Accepted(), batch);
}

TEST(IncrementalVerifier, CandidatesWaitForTheirPoses) {
  RrrOptions options;
  IncrementalVerifier<Pose2> v(options);
  v.AddFirstPose(0, Pose2());
  const Pose2::Jacobian info = Pose2::Jacobian::Identity() * 100;
  const int c = v.AddLoop(5, 0, Pose2(-5, 0, 0), info);
  EXPECT_EQ(v.num_waiting(), 1);
  EXPECT_EQ(v.loop_of(c), -1);
  for (int k = 0; k < 5; ++k) v.AddOdometry(Pose2(1, 0, 0), info);
  EXPECT_EQ(v.num_waiting(), 0);
  EXPECT_EQ(v.loop_of(c), 0);
  EXPECT_EQ(v.state(c), LoopState::kPending);
  v.Finish();
  EXPECT_EQ(v.state(c), LoopState::kAccepted);  // it agrees with odometry
}

// The reason a degenerate candidate was refused, or "kept".
std::string Refusal(OnlineVerifier<Pose2>* v, PoseId a, PoseId b,
                    const Pose2& z) {
  try {
    v->AddLoop(a, b, z, Pose2::Jacobian::Identity());
  } catch (const DegenerateCandidate& e) {
    return ToString(e.defect());
  }
  return "kept";
}

TEST(IncrementalVerifier, RefusesDegenerateCandidatesByReason) {
  RrrOptions options;
  IncrementalVerifier<Pose2> v(options);
  EXPECT_THROW(v.AddOdometry(Pose2(), Pose2::Jacobian::Identity()),
               std::logic_error);
  v.AddFirstPose(10, Pose2());
  EXPECT_EQ(Refusal(&v, 12, 12, Pose2()), "self_loop");
  EXPECT_EQ(Refusal(&v, 11, 10, Pose2()), "consecutive_poses");
  EXPECT_EQ(Refusal(&v, 3, 20, Pose2()), "unknown_pose");
  EXPECT_EQ(Refusal(&v, 20, 30, Pose2(1, 0, 0)), "kept");  // waits for 30
  EXPECT_EQ(Refusal(&v, 20, 30, Pose2(1, 0, 0)), "duplicate");
  EXPECT_EQ(Refusal(&v, 20, 30, Pose2(1, 0.5, 0)), "kept");  // judged too
  EXPECT_EQ(v.num_candidates(), 2);
}

// A level, and whether decisions are reversed in both directions on the way.
struct BicoccaLevel {
  std::string level;
  bool reverses;
};

class IncrementalBicocca : public ::testing::TestWithParam<BicoccaLevel> {};

TEST_P(IncrementalBicocca, EndsWithTheBatchDecisions) {
  std::string missing;
  const auto bicocca = testing::ReadBicocca(GetParam().level, &missing);
  if (!bicocca) GTEST_SKIP() << missing;
  const PoseGraph2& graph = *bicocca;
  RrrOptions options;
  options.cluster_window = 50;
  const Replay replay(graph, options);
  EXPECT_EQ(replay.Accepted(), BatchAccepted(graph, options));
  // New evidence both drops accepted loops and revives rejected ones before
  // the end, where the decisions still equal batch.
  if (GetParam().reverses) {
    EXPECT_GT(replay.accepted_then_rejected, 0);
    EXPECT_GT(replay.rejected_then_accepted, 0);
  }
}

INSTANTIATE_TEST_SUITE_P(Levels, IncrementalBicocca,
                         ::testing::Values(BicoccaLevel{"0.000", true},
                                           BicoccaLevel{"0.150", true},
                                           BicoccaLevel{"0.500", false}),
                         [](const auto& info) {
                           std::string name = "level_" + info.param.level;
                           std::replace(name.begin(), name.end(), '.', '_');
                           return name;
                         });

}  // namespace
}  // namespace rrr
