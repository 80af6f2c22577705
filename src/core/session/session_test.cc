// A session of one robot or a fleet: readings become keyframes and sessions,
// candidates by id or by stamp reach the procedure or are skipped with their
// reason, and an odometry restart starts a session that only loops join.
#include "rrr/session/session.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "../testing/chain_worlds.h"
#include "../testing/scratch_dir.h"
#include "rrr/geometry/pose2.h"
#include "rrr/io/g2o.h"
#include "rrr/solver/pose_graph_solver.h"

namespace rrr {
namespace {

using testing::ChainWorldOptions;
using testing::Grid;
using testing::Readings;

using Information = Constraint<Pose2>::Information;

SessionOptions Options() {
  SessionOptions options;
  options.rrr = ChainWorldOptions();
  return options;
}

// The skips a session reports.
struct Skips {
  std::vector<SkippedMessage> told;
  Session<Pose2>::OnSkip callback() {
    return [this](const SkippedMessage& s) { told.push_back(s); };
  }
};

// The translation RMS (m) of `path` against the optimum of `graph` (one
// chain, every loop) over its poses `first`..., both taken relative to their
// first pose.
double RmsToOptimum(const PoseGraph<Pose2>& graph,
                    const std::vector<Pose2>& path, int first) {
  MinimizeResult result;
  const std::vector<Pose2> optimum = PoseGraphSolver<Pose2>(graph, 1).Optimize(
      AllLoops(graph), ConvergenceOptions{}, &result, &graph.estimates());
  double squares = 0.0;
  for (size_t k = 0; k < path.size(); ++k) {
    const Pose2 got = path[0].between(path[k]);
    const Pose2 best = optimum[first].between(optimum[first + k]);
    squares += (got.translation() - best.translation()).squaredNorm();
  }
  return std::sqrt(squares / static_cast<double>(path.size()));
}

TEST(Session, OneRobotKeepsTheTrueLoopsOfASimulatedRobot) {
  WorldOptions world_options;
  world_options.poses = 600;
  world_options.false_loops = 20;
  const SimulatedWorld world = SimulateWorld(world_options);
  const PoseGraph<Pose2>& g = world.graph;
  const auto readings = Readings(g, 0, g.num_poses() - 1, 0);
  Skips skips;
  Session<Pose2> session({""}, Options(), skips.callback());
  std::vector<int> candidate_of_loop(g.loops().size(), -1);
  for (int p = 0; p < g.num_poses(); ++p) {
    const auto taken = session.AddReading(0, readings[p]);
    ASSERT_TRUE(taken.problem.empty()) << taken.problem;
    ASSERT_TRUE(taken.keyframe);
    ASSERT_EQ(taken.id, p);
    EXPECT_EQ(taken.new_session, p == 0);
    for (size_t k = 0; k < g.loops().size(); ++k) {
      const auto& l = g.loops()[k];
      if (std::max(l.from, l.to) != p) continue;
      candidate_of_loop[k] = session.verifier().num_candidates();
      session.AddCandidate(static_cast<int>(k), 0, l.from, 0, l.to,
                           l.measurement, l.information);
    }
    ASSERT_TRUE(session.Update(false).store_error.empty());
  }
  session.Update(true);
  int true_loops = 0, kept = 0;
  for (size_t k = 0; k < g.loops().size(); ++k) {
    const bool is_false =
        std::count(world.false_loops.begin(), world.false_loops.end(), k) > 0;
    const bool is_accepted =
        session.verifier().state(candidate_of_loop[k]) == LoopState::kAccepted;
    EXPECT_FALSE(is_false && is_accepted) << "false loop " << k << " accepted";
    true_loops += !is_false;
    kept += !is_false && is_accepted;
    EXPECT_EQ(session.from(candidate_of_loop[k]).id, g.loops()[k].from);
  }
  EXPECT_GE(kept, 0.9 * true_loops) << kept << " of " << true_loops;
  EXPECT_TRUE(skips.told.empty());
  // The map: every keyframe corrected, the newest one's correction on tf.
  EXPECT_EQ(session.num_chains(), 1);
  const std::vector<Pose2> path = session.Path(0, session.MapOfRobot(0));
  ASSERT_EQ(path.size(), readings.size());
  EXPECT_EQ(session.PathStamps(0, 0).back(), readings.back().stamp_ns);
  const Pose2 by_correction =
      *session.MapToOdom(0) * readings.back().odometry_pose;
  EXPECT_LT((path.back().translation() - by_correction.translation()).norm(),
            1e-6);
}

TEST(Session, AnOdometryRestartStartsASessionJoinedOnlyByItsLoops) {
  // One robot drives a world; at pose 500 its odometry restarts at zero.
  // Every loop of the world comes as a candidate by keyframe, those that
  // span the restart between its two sessions.
  const SimulatedWorld world = SimulateWorld(Grid(1000, 2));
  const PoseGraph<Pose2>& graph = world.graph;
  Session<Pose2> session({""}, Options(), nullptr);
  std::vector<KeyframeRecord<Pose2>> readings = Readings(graph, 0, 499, 0);
  const std::vector<KeyframeRecord<Pose2>> after =
      Readings(graph, 500, 999, readings.back().stamp_ns + 20'000'000);
  readings.insert(readings.end(), after.begin(), after.end());
  ASSERT_EQ(readings.size(), 1000u);
  for (int k = 0; k < 1000; ++k) {
    const auto taken = session.AddReading(0, readings[k]);
    ASSERT_TRUE(taken.problem.empty()) << taken.problem;
    EXPECT_EQ(taken.id, k);
    EXPECT_EQ(taken.new_session, k == 0 || k == 500) << k;
    EXPECT_FALSE(taken.restarted);
    for (const auto& e : graph.loops()) {
      if (std::max(e.from, e.to) != k) continue;
      session.AddCandidate(0, 0, e.from, 0, e.to, e.measurement, e.information);
    }
    if (k % 10 == 9) session.Update(false);
  }
  session.Update(true);

  ASSERT_EQ(session.sessions(0).size(), 2u);
  EXPECT_EQ(session.Graph().odometry().size(), 998u)
      << "none across the restart";
  EXPECT_EQ(session.MapOfRobot(0), 0) << "the sessions joined";
  EXPECT_GE(session.verifier().num_in_state(LoopState::kAccepted),
            0.95 * static_cast<double>(graph.loops().size()));
  // Both sessions in one frame, where the optimum of the world as one chain
  // with every loop puts them.
  const std::vector<Pose2> path = session.Path(0, 0);
  ASSERT_EQ(path.size(), 1000u);
  EXPECT_LT(RmsToOptimum(graph, path, 0), 0.25);
  // map -> odom takes the second session's odometry to the map.
  const Pose2 corrected = *session.MapToOdom(0) * readings.back().odometry_pose;
  EXPECT_LT((corrected.translation() - path.back().translation()).norm(), 1e-6);
}

TEST(Session, ARestartIsAStampBackOrAReadingBackAtTheOriginFarFromIt) {
  Session<Pose2> session({""}, Options(), nullptr);
  KeyframeRecord<Pose2> reading;
  reading.stamp_ns = 1'000;
  EXPECT_TRUE(session.AddReading(0, reading).new_session);
  // Near the origin and back there: no restart.
  for (const Pose2& pose : {Pose2(0.5, 0.0, 0.0), Pose2()}) {
    reading.stamp_ns += 1'000;
    reading.odometry_pose = pose;
    EXPECT_FALSE(session.AddReading(0, reading).new_session);
  }
  reading.stamp_ns += 1'000;
  reading.odometry_pose = Pose2(6.0, 0.0, 0.0);
  EXPECT_FALSE(session.AddReading(0, reading).new_session) << "a long step";
  reading.stamp_ns += 1'000;
  reading.odometry_pose = Pose2();
  EXPECT_TRUE(session.AddReading(0, reading).new_session) << "back at zero";
  reading.stamp_ns -= 500;
  const auto back = session.AddReading(0, reading);
  EXPECT_TRUE(back.new_session) << "back in time";
  EXPECT_EQ(back.id, 5);
  EXPECT_EQ(session.sessions(0).size(), 3u);
  EXPECT_EQ(session.Graph().odometry().size(), 3u);

  SessionOptions off = Options();
  off.restart_jump = 0.0;
  Session<Pose2> not_looked_for({""}, off, nullptr);
  reading.odometry_pose = Pose2(50.0, 0.0, 0.0);
  not_looked_for.AddReading(0, reading);
  reading.stamp_ns += 1'000;
  reading.odometry_pose = Pose2();
  EXPECT_FALSE(not_looked_for.AddReading(0, reading).new_session);
}

TEST(Session, ThePublishedProcedureJoinsARestartByItsJumpAndSaysSo) {
  SessionOptions options = Options();
  options.rrr.procedure = Procedure::kPublished;
  Session<Pose2> session({""}, options, nullptr);
  KeyframeRecord<Pose2> reading;
  for (const double x : {0.0, 2.0, 4.0}) {
    reading.stamp_ns += 1'000;
    reading.odometry_pose = Pose2(x, 0.0, 0.0);
    EXPECT_FALSE(session.AddReading(0, reading).restarted);
  }
  reading.stamp_ns += 1'000;
  reading.odometry_pose = Pose2();
  const auto taken = session.AddReading(0, reading);
  EXPECT_TRUE(taken.keyframe);
  EXPECT_FALSE(taken.new_session);
  EXPECT_TRUE(taken.restarted);
  EXPECT_NEAR(taken.jump, 4.0, 1e-12);
  EXPECT_EQ(session.num_chains(), 1);
  EXPECT_EQ(session.verifier().graph().odometry().size(), 3u);
  // A reading stamped before the last is refused: one chain cannot take it.
  reading.stamp_ns -= 500;
  EXPECT_FALSE(session.AddReading(0, reading).problem.empty());
  // Nor does it judge a fleet.
  EXPECT_THROW(Session<Pose2>({"a", "b"}, options, nullptr),
               std::invalid_argument);
}

TEST(Session, TwoRobotsJoinedByTheirLoopsShareOneMapFrame) {
  // Two robots of one world, the second starting at its pose 400, its
  // odometry at zero there; the loops between them join them.
  const SimulatedWorld world = SimulateWorld(Grid(800, 5));
  const PoseGraph<Pose2>& graph = world.graph;
  Session<Pose2> session({"a", "b"}, Options(), nullptr);
  const auto first = Readings(graph, 0, 399, 0);
  const auto second = Readings(graph, 400, 799, 0);
  const auto robot_and_id = [](int p) {
    return std::pair(p < 400 ? 0 : 1, p < 400 ? p : p - 400);
  };
  std::vector<int> between;  // candidates
  for (int k = 0; k < 400; ++k) {
    session.AddReading(0, first[k]);
    session.AddReading(1, second[k]);
    // Loops once both ends exist (robot b's pose p - 400 comes at round
    // p - 400).
    for (const auto& e : graph.loops()) {
      const auto [ra, ia] = robot_and_id(e.from);
      const auto [rb, ib] = robot_and_id(e.to);
      if (std::max(ia, ib) != k) continue;
      if (ra != rb) between.push_back(session.verifier().num_candidates());
      session.AddCandidate(0, ra, ia, rb, ib, e.measurement, e.information);
    }
    if (k % 10 == 9) session.Update(false);
  }
  session.Update(true);
  ASSERT_FALSE(between.empty());
  EXPECT_EQ(session.MapOfRobot(1), 0);
  int kept = 0;
  for (const int c : between) {
    kept += session.verifier().state(c) == LoopState::kAccepted;
    EXPECT_NE(session.from(c).chain, session.to(c).chain);
  }
  EXPECT_GE(kept, 0.95 * static_cast<double>(between.size()));
  // Robot b placed in robot a's frame where the optimum of the whole world
  // (one chain, every loop) puts it.
  const std::vector<Pose2> path = session.Path(1, 0);
  ASSERT_EQ(path.size(), 400u);
  MinimizeResult result;
  const std::vector<Pose2> optimum = PoseGraphSolver<Pose2>(graph, 1).Optimize(
      AllLoops(graph), ConvergenceOptions{}, &result, &graph.estimates());
  const Pose2 start = optimum[0].between(optimum[400]);
  EXPECT_LT((path[0].translation() - start.translation()).norm(), 0.25);
  const Pose2 corrected = *session.MapToOdom(1) * second.back().odometry_pose;
  EXPECT_LT((corrected.translation() - path.back().translation()).norm(), 1e-6);

  // The map's accepted graph: both robots' keyframes at their corrected
  // poses, their odometry, and every accepted loop.
  const auto accepted = session.AcceptedGraph(0);
  ASSERT_EQ(accepted.graph.num_poses(), 800);
  EXPECT_EQ(accepted.graph.odometry().size(), 798u);
  EXPECT_EQ(static_cast<int>(accepted.graph.loops().size()),
            session.verifier().num_in_state(LoopState::kAccepted));
  EXPECT_EQ(accepted.robot[399], 0);
  EXPECT_EQ(accepted.robot[400], 1);
  EXPECT_EQ(accepted.keyframe[400], 0);
  EXPECT_EQ(accepted.keyframe[799], 399);
  EXPECT_LT((accepted.graph.estimates()[799].translation() -
             path.back().translation())
                .norm(),
            1e-9);
  EXPECT_EQ(session.AcceptedGraph(1).graph.num_poses(), 0) << "not a map";
}

TEST(Session, WithADatabaseTakesNoInputBeforeResume) {
  testing::ScratchDir dir;
  SessionOptions options;
  options.database = dir.File("session.db");
  Session<Pose2> session({""}, options, nullptr);
  KeyframeRecord<Pose2> reading;
  reading.stamp_ns = 1;
  EXPECT_THROW(session.AddReading(0, reading), std::logic_error);
  EXPECT_THROW(session.Update(false), std::logic_error);
  session.Resume();
  EXPECT_TRUE(session.AddReading(0, reading).keyframe);
  EXPECT_EQ(session.Update(false).store_error, "");
}

TEST(Session, SkipsACandidateItCannotJudgeWithItsReason) {
  Skips skips;
  Session<Pose2> session({""}, Options(), skips.callback());
  KeyframeRecord<Pose2> reading;
  for (int k = 0; k < 5; ++k) {
    reading.stamp_ns += 1'000'000'000;
    reading.odometry_pose = Pose2(k, 0.0, 0.0);
    session.AddReading(0, reading);
  }
  const Information information = Information::Identity();
  session.AddCandidate(7, 0, 2, 0, 2, Pose2(), information);
  session.AddCandidate(8, 0, -1, 0, 3, Pose2(), information);
  session.AddCandidate(9, 0, 1, 0, 2, Pose2(1.0, 0.0, 0.0), information);
  ASSERT_EQ(skips.told.size(), 3u);
  EXPECT_EQ(skips.told[0].message, 7);
  EXPECT_EQ(skips.told[0].defect, CandidateDefect::kSelfLoop);
  EXPECT_EQ(skips.told[1].message, 8);
  EXPECT_EQ(skips.told[1].defect, CandidateDefect::kUnknownPose);
  EXPECT_EQ(skips.told[2].defect, CandidateDefect::kConsecutivePoses);
  EXPECT_EQ(session.verifier().num_candidates(), 0);
}

TEST(Session, RobotsAreNamedOnceAndCandidatesWaitForTheirRobots) {
  EXPECT_THROW(Session<Pose2>({}, Options(), nullptr), std::invalid_argument);
  EXPECT_THROW(Session<Pose2>({"a", "a"}, Options(), nullptr),
               std::invalid_argument);
  EXPECT_THROW(Session<Pose2>({"a", ""}, Options(), nullptr),
               std::invalid_argument);
  SessionOptions bad = Options();
  bad.odometry.keyframe_translation = -1.0;
  EXPECT_THROW(Session<Pose2>({"a"}, bad, nullptr), std::invalid_argument);
  bad = Options();
  bad.odometry.odometry_information = {1.0, 1.0};
  EXPECT_THROW(Session<Pose2>({"a"}, bad, nullptr), std::invalid_argument);
  bad = Options();
  bad.rrr.cluster_window = 0;
  EXPECT_THROW(Session<Pose2>({"a"}, bad, nullptr), std::invalid_argument);
  bad = Options();
  bad.restart_jump = -1.0;
  EXPECT_THROW(Session<Pose2>({"a"}, bad, nullptr), std::invalid_argument);

  Session<Pose2> session({"a", "b"}, Options(), nullptr);
  EXPECT_EQ(session.RobotIndex("b"), 1);
  EXPECT_EQ(session.RobotIndex("c"), -1);
  session.AddReading(0, {});
  EXPECT_EQ(session.MapOfRobot(1), -1);
  EXPECT_FALSE(session.MapToOdom(1));
  const Information information = Information::Identity();
  // Robot b has no keyframe yet (its process started later): the candidate
  // waits for it, and is added with its first keyframe.
  session.AddCandidate(0, 0, 0, 1, 0, Pose2(), information);
  EXPECT_EQ(session.num_waiting_for_robots(), 1);
  EXPECT_EQ(session.verifier().num_candidates(), 0);
  session.AddReading(1, {});
  EXPECT_EQ(session.num_waiting_for_robots(), 0);
  EXPECT_EQ(session.verifier().num_candidates(), 1);
  EXPECT_THROW(session.AddCandidate(1, 0, 0, 3, 0, Pose2(), information),
               std::out_of_range);
  EXPECT_THROW(session.AddReading(2, {}), std::out_of_range);
}

TEST(Session, CandidatesByStampNameTheNearestKeyframeOnceItIsThere) {
  SessionOptions options = Options();
  options.odometry.stamp_tolerance_ns = 5'000'000;  // readings 20 ms apart
  Skips skips;
  Session<Pose2> session({"a", "b"}, options, skips.callback());
  const SimulatedWorld world = SimulateWorld(Grid(100, 3));
  const auto a = Readings(world.graph, 0, 29, 1'000'000'000);
  const auto b = Readings(world.graph, 30, 59, 1'000'000'000);
  const Information information = Information::Identity();
  for (int k = 0; k < 10; ++k) session.AddReading(0, a[k]);
  // Robot b has no keyframe yet; a's end is 3 ms from its keyframe 5.
  session.AddCandidateByStamp(1, 0, a[5].stamp_ns + 3'000'000, 1, b[3].stamp_ns,
                              Pose2(), information);
  // b's end falls between two of its keyframes, 10 ms from each.
  session.AddCandidateByStamp(2, 0, a[2].stamp_ns, 1,
                              b[4].stamp_ns + 10'000'000, Pose2(), information);
  EXPECT_EQ(session.num_waiting_by_stamp(), 2);
  for (int k = 0; k < 3; ++k) session.AddReading(1, b[k]);
  EXPECT_EQ(session.num_waiting_by_stamp(), 2) << "b's keyframe 3 not there";
  session.AddReading(1, b[3]);
  ASSERT_EQ(session.verifier().num_candidates(), 1);
  EXPECT_EQ(session.from(0).id, 5);
  EXPECT_EQ(session.to(0).id, 3);
  EXPECT_EQ(session.robot_of_chain(session.to(0).chain), 1);
  session.AddReading(1, b[4]);
  session.AddReading(1, b[5]);
  EXPECT_EQ(session.num_waiting_by_stamp(), 0);
  ASSERT_EQ(skips.told.size(), 1u) << "no keyframe within 5 ms";
  EXPECT_EQ(skips.told[0].message, 2);
  EXPECT_EQ(skips.told[0].defect, CandidateDefect::kUnknownPose);
  EXPECT_EQ(session.verifier().num_candidates(), 1);
  // Settled at once; a stamp before a's first keyframe names none.
  session.AddCandidateByStamp(3, 0, a[7].stamp_ns, 1, b[1].stamp_ns, Pose2(),
                              information);
  EXPECT_EQ(session.verifier().num_candidates(), 2);
  session.AddCandidateByStamp(4, 0, a[0].stamp_ns - 1'000'000'000, 1,
                              b[1].stamp_ns, Pose2(), information);
  ASSERT_EQ(skips.told.size(), 2u);
  EXPECT_EQ(skips.told[1].message, 4);
  // After a restart whose stamps start over, a stamp of the first session
  // still names its keyframe there; one in both, the newest session's.
  const auto again = Readings(world.graph, 10, 29, a[5].stamp_ns);
  for (const auto& reading : again) session.AddReading(0, reading);
  ASSERT_EQ(session.sessions(0).size(), 2u);
  for (const int k : {1, 6}) {
    session.AddCandidateByStamp(5 + k, 0, a[k].stamp_ns, 1, b[1].stamp_ns,
                                Pose2(), information);
  }
  ASSERT_EQ(session.verifier().num_candidates(), 4);
  EXPECT_EQ(session.from(2).id, 1);
  EXPECT_EQ(session.from(2).chain, session.sessions(0)[0]);
  EXPECT_EQ(session.from(3).id, 11);
  EXPECT_EQ(session.from(3).chain, session.sessions(0)[1]);
}

}  // namespace
}  // namespace rrr
