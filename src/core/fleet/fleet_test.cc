#include "rrr/fleet/fleet.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "../testing/chain_worlds.h"
#include "rrr/geometry/pose2.h"
#include "rrr/graph/candidate_defect.h"
#include "rrr/io/g2o.h"
#include "rrr/solver/pose_graph_solver.h"

namespace rrr {
namespace {

using testing::ChainWorldOptions;
using testing::Grid;
using testing::Readings;

FleetOptions Options() {
  FleetOptions options;
  options.rrr = ChainWorldOptions();
  // The worlds' readings are their poses, about a metre apart.
  options.restart_jump = 3.0;
  return options;
}

TEST(Fleet, ARobotThatRestartsContinuesInASessionJoinedOnlyByItsLoops) {
  // One robot drives a world; at pose 500 its odometry restarts at zero.
  // Every loop of the world comes as a candidate by keyframe, those that
  // span the restart between its two sessions.
  const SimulatedWorld world = SimulateWorld(Grid(1000, 2));
  const PoseGraph<Pose2>& graph = world.graph;
  Fleet<Pose2> fleet({"scout"}, Options());
  std::vector<KeyframeRecord<Pose2>> readings = Readings(graph, 0, 499, 0);
  const std::vector<KeyframeRecord<Pose2>> after =
      Readings(graph, 500, 999, readings.back().stamp_ns + 20'000'000);
  readings.insert(readings.end(), after.begin(), after.end());
  ASSERT_EQ(readings.size(), 1000u);
  for (int k = 0; k < 1000; ++k) {
    const Fleet<Pose2>::Taken taken = fleet.AddReading(0, readings[k]);
    ASSERT_TRUE(taken.problem.empty()) << taken.problem;
    EXPECT_EQ(taken.id, k);
    EXPECT_EQ(taken.new_session, k == 0 || k == 500) << k;
    for (const auto& e : graph.loops()) {
      if (std::max(e.from, e.to) != k) continue;
      fleet.AddLoop(0, e.from, 0, e.to, e.measurement, e.information);
    }
    if (k % 10 == 9) fleet.Update();
  }
  fleet.Finish();

  ASSERT_EQ(fleet.sessions(0).size(), 2u);
  const PoseGraph<Pose2> recorded = fleet.Graph();
  EXPECT_EQ(recorded.odometry().size(), 998u) << "none across the restart";
  EXPECT_EQ(fleet.MapOfRobot(0), 0) << "the sessions joined";
  EXPECT_GE(fleet.verifier().num_in_state(LoopState::kAccepted),
            0.95 * static_cast<double>(graph.loops().size()));
  // Both sessions in one frame, where the optimum of the world as one chain
  // with every loop puts them.
  const std::vector<Pose2> path = fleet.Path(0, 0);
  ASSERT_EQ(path.size(), 1000u);
  MinimizeResult result;
  const std::vector<Pose2> optimum = PoseGraphSolver<Pose2>(graph, 1).Optimize(
      AllLoops(graph), ConvergenceOptions{}, &result, &graph.estimates());
  double squares = 0.0;
  for (int k = 0; k < 1000; ++k) {
    const Pose2 got = path[0].between(path[k]);
    const Pose2 best = optimum[0].between(optimum[k]);
    squares += (got.translation() - best.translation()).squaredNorm();
  }
  EXPECT_LT(std::sqrt(squares / 1000.0), 0.25) << "RMS error, m";
  // map -> odom takes the second session's odometry to the map.
  const Pose2 corrected = *fleet.MapToOdom(0) * readings.back().odometry_pose;
  EXPECT_LT((corrected.translation() - path.back().translation()).norm(), 1e-6);
}

TEST(Fleet, TwoRobotsJoinedByTheirLoopsShareOneMapFrame) {
  // Two robots of one world, the second starting at its pose 400, its
  // odometry at zero there; the loops between them join them.
  const SimulatedWorld world = SimulateWorld(Grid(800, 5));
  const PoseGraph<Pose2>& graph = world.graph;
  Fleet<Pose2> fleet({"a", "b"}, Options());
  const auto first = Readings(graph, 0, 399, 0);
  const auto second = Readings(graph, 400, 799, 0);
  const auto robot_and_id = [](int p) {
    return std::pair(p < 400 ? 0 : 1, p < 400 ? p : p - 400);
  };
  std::vector<std::pair<int, int>> between;  // (loop, candidate)
  for (int k = 0; k < 400; ++k) {
    fleet.AddReading(0, first[k]);
    fleet.AddReading(1, second[k]);
    // Loops once both ends exist (robot b's pose p - 400 comes at round
    // p - 400).
    for (size_t l = 0; l < graph.loops().size(); ++l) {
      const auto& e = graph.loops()[l];
      const auto [ra, ia] = robot_and_id(e.from);
      const auto [rb, ib] = robot_and_id(e.to);
      if (std::max(ia, ib) != k) continue;
      const int c = fleet.AddLoop(ra, ia, rb, ib, e.measurement, e.information);
      if (ra != rb) between.emplace_back(static_cast<int>(l), c);
    }
    if (k % 10 == 9) fleet.Update();
  }
  fleet.Finish();
  ASSERT_FALSE(between.empty());
  EXPECT_EQ(fleet.MapOfRobot(1), 0);
  int kept = 0;
  for (const auto& [loop, candidate] : between) {
    kept += fleet.verifier().state(candidate) == LoopState::kAccepted;
  }
  EXPECT_GE(kept, 0.95 * static_cast<double>(between.size()));
  // Robot b placed in robot a's frame where the optimum of the whole world
  // (one chain, every loop) puts it.
  const std::vector<Pose2> path = fleet.Path(1, 0);
  ASSERT_EQ(path.size(), 400u);
  MinimizeResult result;
  const std::vector<Pose2> optimum = PoseGraphSolver<Pose2>(graph, 1).Optimize(
      AllLoops(graph), ConvergenceOptions{}, &result, &graph.estimates());
  const Pose2 start = optimum[0].between(optimum[400]);
  EXPECT_LT((path[0].translation() - start.translation()).norm(), 0.25);
  const Pose2 corrected = *fleet.MapToOdom(1) * second.back().odometry_pose;
  EXPECT_LT((corrected.translation() - path.back().translation()).norm(), 1e-6);

  // The map's accepted graph: both robots' keyframes at their corrected
  // poses, their odometry, and every accepted loop.
  const FleetGraph<Pose2> accepted = fleet.AcceptedGraph(0);
  ASSERT_EQ(accepted.graph.num_poses(), 800);
  EXPECT_EQ(accepted.graph.odometry().size(), 798u);
  EXPECT_EQ(static_cast<int>(accepted.graph.loops().size()),
            fleet.verifier().num_in_state(LoopState::kAccepted));
  EXPECT_EQ(accepted.robot[399], 0);
  EXPECT_EQ(accepted.robot[400], 1);
  EXPECT_EQ(accepted.keyframe[400], 0);
  EXPECT_EQ(accepted.keyframe[799], 399);
  EXPECT_LT((accepted.graph.estimates()[799].translation() -
             path.back().translation())
                .norm(),
            1e-9);
  EXPECT_EQ(fleet.AcceptedGraph(1).graph.num_poses(), 0) << "not a map";
}

TEST(Fleet, AJumpABackwardStampOrARequestStartsANewSession) {
  Fleet<Pose2> fleet({"a"}, Options());
  KeyframeRecord<Pose2> reading;
  reading.stamp_ns = 1'000;
  EXPECT_TRUE(fleet.AddReading(0, reading).new_session);
  reading.stamp_ns += 1'000;
  reading.odometry_pose = Pose2(2.5, 0.0, 0.0);
  EXPECT_FALSE(fleet.AddReading(0, reading).new_session) << "a step";
  reading.stamp_ns += 1'000;
  reading.odometry_pose = Pose2(6.0, 0.0, 0.0);
  EXPECT_TRUE(fleet.AddReading(0, reading).new_session) << "a jump";
  reading.stamp_ns -= 500;
  EXPECT_TRUE(fleet.AddReading(0, reading).new_session) << "back in time";
  fleet.StartSession(0);
  reading.stamp_ns += 1'000;
  const Fleet<Pose2>::Taken taken = fleet.AddReading(0, reading);
  EXPECT_TRUE(taken.new_session) << "asked";
  EXPECT_EQ(taken.id, 4);
  EXPECT_EQ(fleet.sessions(0).size(), 4u);
  EXPECT_EQ(fleet.Graph().odometry().size(), 1u);

  FleetOptions off = Options();
  off.restart_jump = 0.0;
  Fleet<Pose2> no_jumps({"a"}, off);
  reading.odometry_pose = Pose2();
  no_jumps.AddReading(0, reading);
  reading.stamp_ns += 1'000;
  reading.odometry_pose = Pose2(50.0, 0.0, 0.0);
  EXPECT_FALSE(no_jumps.AddReading(0, reading).new_session);
}

TEST(Fleet, RobotsAreNamedOnceAndCandidatesWaitForTheirRobots) {
  EXPECT_THROW(Fleet<Pose2>({}, Options()), std::invalid_argument);
  EXPECT_THROW(Fleet<Pose2>({"a", "a"}, Options()), std::invalid_argument);
  EXPECT_THROW(Fleet<Pose2>({"a", ""}, Options()), std::invalid_argument);
  FleetOptions negative_threshold = Options();
  negative_threshold.odometry.keyframe_translation = -1.0;
  EXPECT_THROW(Fleet<Pose2>({"a"}, negative_threshold), std::invalid_argument);
  Fleet<Pose2> fleet({"a", "b"}, Options());
  EXPECT_EQ(fleet.RobotIndex("b"), 1);
  EXPECT_EQ(fleet.RobotIndex("c"), -1);
  fleet.AddReading(0, {});
  const Eigen::Matrix3d information = Eigen::Matrix3d::Identity();
  // Robot b has no keyframe yet (its process started later): the
  // candidate waits for it, and is added with its first keyframe.
  EXPECT_EQ(fleet.AddLoop(0, 0, 1, 0, Pose2(), information), -1);
  EXPECT_EQ(fleet.num_waiting_for_robots(), 1);
  EXPECT_EQ(fleet.verifier().num_candidates(), 0);
  fleet.AddReading(1, {});
  EXPECT_EQ(fleet.num_waiting_for_robots(), 0);
  EXPECT_EQ(fleet.verifier().num_candidates(), 1);
  EXPECT_EQ(fleet.refused_waiting(), 0);
  EXPECT_THROW(fleet.AddLoop(0, 0, 3, 0, Pose2(), information),
               std::out_of_range);
  EXPECT_THROW(fleet.AddReading(2, {}), std::out_of_range);
}

TEST(Fleet, CandidatesByStampNameTheNearestKeyframeOnceItIsThere) {
  FleetOptions options = Options();
  options.odometry.stamp_tolerance_ns = 5'000'000;  // readings come 20 ms apart
  Fleet<Pose2> fleet({"a", "b"}, options);
  const SimulatedWorld world = SimulateWorld(Grid(100, 3));
  const auto a = Readings(world.graph, 0, 29, 1'000'000'000);
  const auto b = Readings(world.graph, 30, 59, 1'000'000'000);
  const Eigen::Matrix3d information = Eigen::Matrix3d::Identity();
  for (int k = 0; k < 10; ++k) fleet.AddReading(0, a[k]);
  // Robot b has no keyframe yet; a's end is 3 ms from its keyframe 5.
  EXPECT_EQ(fleet.AddLoopByStamp(0, a[5].stamp_ns + 3'000'000, 1, b[3].stamp_ns,
                                 Pose2(), information),
            -1);
  // b's end falls between two of its keyframes, 10 ms from each.
  EXPECT_EQ(
      fleet.AddLoopByStamp(0, a[2].stamp_ns, 1, b[4].stamp_ns + 10'000'000,
                           Pose2(), information),
      -1);
  EXPECT_EQ(fleet.num_waiting_by_stamp(), 2);
  for (int k = 0; k < 3; ++k) fleet.AddReading(1, b[k]);
  EXPECT_EQ(fleet.num_waiting_by_stamp(), 2) << "b's keyframe 3 not there";
  fleet.AddReading(1, b[3]);
  ASSERT_EQ(fleet.verifier().num_candidates(), 1);
  EXPECT_EQ(fleet.from(0).id, 5);
  EXPECT_EQ(fleet.to(0).id, 3);
  EXPECT_EQ(fleet.robot_of_chain(fleet.to(0).chain), 1);
  fleet.AddReading(1, b[4]);
  fleet.AddReading(1, b[5]);
  EXPECT_EQ(fleet.num_waiting_by_stamp(), 0);
  EXPECT_EQ(fleet.refused_by_stamp(), 1) << "no keyframe within 5 ms";
  EXPECT_EQ(fleet.verifier().num_candidates(), 1);
  // Settled at once; a stamp before a's first keyframe names none.
  EXPECT_EQ(fleet.AddLoopByStamp(0, a[7].stamp_ns, 1, b[1].stamp_ns, Pose2(),
                                 information),
            1);
  try {
    fleet.AddLoopByStamp(0, a[0].stamp_ns - 1'000'000'000, 1, b[1].stamp_ns,
                         Pose2(), information);
    ADD_FAILURE() << "taken";
  } catch (const DegenerateCandidate& e) {
    EXPECT_EQ(e.defect(), CandidateDefect::kUnknownPose);
  }
  // After a restart whose stamps start over, a stamp of the first session
  // still names its keyframe there.
  fleet.StartSession(0);
  const auto again = Readings(world.graph, 10, 29, a[5].stamp_ns);
  for (const auto& reading : again) fleet.AddReading(0, reading);
  ASSERT_EQ(fleet.sessions(0).size(), 2u);
  EXPECT_EQ(fleet.KeyframeAt(0, a[1].stamp_ns), 1);
  EXPECT_EQ(fleet.KeyframeAt(0, a[6].stamp_ns), 11) << "in both: the newest";
  EXPECT_EQ(fleet.KeyframeAt(0, again.back().stamp_ns + 1'000'000'000),
            KeyframeStamps::kNotYet);
}

}  // namespace
}  // namespace rrr
