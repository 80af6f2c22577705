// One robot's session: readings become keyframes, candidates by id or by
// stamp reach the procedure or are skipped with their reason, and a session
// opened again on its database takes up where it stopped.
#include "rrr/session/robot_session.h"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <algorithm>
#include <map>
#include <utility>

#include "../testing/scratch_dir.h"
#include "rrr/geometry/pose2.h"
#include "rrr/sim/simulated_world.h"

namespace rrr {
namespace {

constexpr std::int64_t kSecond = 1'000'000'000;

// A simulated robot's odometry readings (one per second, each a keyframe)
// with the covariance a growing source reports, and its candidates by the
// keyframe ids the session gives (0, 1, ...: the world's pose indices).
class RobotSessionTest : public ::testing::Test {
 protected:
  void SetUp() override {
    WorldOptions world;
    world.poses = 600;
    world.false_loops = 20;
    world_ = SimulateWorld(world);
    const auto& g = world_.graph;
    OdometryCovariance covariance = OdometryCovariance::Zero();
    for (int p = 0; p < g.num_poses(); ++p) {
      if (p > 0) {
        covariance = OdometryNoiseModel<Pose2>::Grow(
            covariance, g.estimates()[p], g.odometry()[p - 1].information);
      }
      readings_.push_back({kSecond * (p + 1), g.estimates()[p], covariance});
    }
    for (size_t k = 0; k < g.loops().size(); ++k) {
      const auto& l = g.loops()[k];
      loops_at_[std::max(l.from, l.to)].push_back(static_cast<int>(k));
    }
  }

  RobotSessionOptions Options(const std::string& database = "") const {
    RobotSessionOptions options;
    options.rrr.cluster_window = 10;
    options.database = database;
    options.checkpoint_keyframes = 100;
    return options;
  }

  // Gives `session` the readings from `first` to `last` - 1, each followed
  // by the candidates whose later pose it is and an update.
  void Drive(RobotSession<Pose2>* session, int first, int last) {
    const auto& g = world_.graph;
    for (int p = first; p < last; ++p) {
      const auto taken = session->AddReading(readings_[p]);
      ASSERT_TRUE(taken.problem.empty()) << taken.problem;
      ASSERT_TRUE(taken.keyframe);
      ASSERT_EQ(taken.id, p);
      for (const int k : loops_at_[p]) {
        const auto& l = g.loops()[k];
        session->AddCandidate(k, l.from, l.to, l.measurement, l.information);
      }
      const auto updated = session->Update(false);
      ASSERT_TRUE(updated.store_error.empty()) << updated.store_error;
    }
  }

  // The ends of the candidates accepted.
  static std::multiset<std::pair<PoseId, PoseId>> Accepted(
      const RobotSession<Pose2>& session) {
    std::multiset<std::pair<PoseId, PoseId>> accepted;
    const OnlineVerifier<Pose2>& verifier = session.verifier();
    for (int c = 0; c < verifier.num_candidates(); ++c) {
      if (verifier.state(c) == LoopState::kAccepted) {
        accepted.insert(verifier.ends_of(c));
      }
    }
    return accepted;
  }

  testing::ScratchDir dir_;
  SimulatedWorld world_;
  std::vector<KeyframeRecord<Pose2>> readings_;
  std::map<int, std::vector<int>> loops_at_;
  std::vector<SkippedMessage> skipped_;
  RobotSession<Pose2>::OnSkip on_skip_ = [this](const SkippedMessage& s) {
    skipped_.push_back(s);
  };
};

TEST_F(RobotSessionTest, KeepsTheTrueLoopsOfASimulatedRobot) {
  RobotSession<Pose2> session(Options(), on_skip_);
  Drive(&session, 0, world_.graph.num_poses());
  const auto finished = session.Update(true);
  EXPECT_TRUE(finished.accepted_changed || !Accepted(session).empty());
  const auto accepted = Accepted(session);
  const auto& loops = world_.graph.loops();
  int true_loops = 0, kept = 0;
  for (int k = 0; k < static_cast<int>(loops.size()); ++k) {
    const bool is_false =
        std::count(world_.false_loops.begin(), world_.false_loops.end(), k) > 0;
    const bool is_accepted = accepted.count({loops[k].from, loops[k].to}) > 0;
    EXPECT_FALSE(is_false && is_accepted) << "false loop " << k << " accepted";
    if (!is_false) {
      ++true_loops;
      kept += is_accepted ? 1 : 0;
    }
  }
  EXPECT_GE(kept, 0.9 * true_loops) << kept << " of " << true_loops;
  EXPECT_TRUE(skipped_.empty());
  // The map: every keyframe corrected, the newest one's correction on tf.
  ASSERT_EQ(session.Map().size(), readings_.size());
  const Pose2 newest = session.Map().back();
  const Pose2 by_correction =
      session.MapToOdom() * readings_.back().odometry_pose;
  EXPECT_NEAR((newest.translation() - by_correction.translation()).norm(), 0.0,
              1e-6);
}

TEST_F(RobotSessionTest, RefusesAReadingStampedBeforeTheNewestKeyframe) {
  RobotSession<Pose2> session(Options(), on_skip_);
  Drive(&session, 0, 3);
  auto late = readings_[1];
  const auto taken = session.AddReading(late);
  EXPECT_FALSE(taken.keyframe);
  EXPECT_FALSE(taken.problem.empty());
  EXPECT_EQ(session.keyframes().size(), 3);
}

TEST_F(RobotSessionTest, AnOdometryRestartedAtZeroIsToldAndJoinedByItsJump) {
  RobotSession<Pose2> session(Options(), on_skip_);
  Drive(&session, 0, 50);
  const Pose2 before = readings_[49].odometry_pose;
  ASSERT_GT(before.translation().norm(), 2.0);
  // The driver starts again: its next message is at zero, then it moves on.
  KeyframeRecord<Pose2> restarted{readings_[49].stamp_ns + kSecond, Pose2(),
                                  OdometryCovariance::Zero()};
  const auto taken = session.AddReading(restarted);
  EXPECT_TRUE(taken.keyframe);
  EXPECT_TRUE(taken.restarted);
  EXPECT_NEAR(taken.jump, before.translation().norm(), 1e-9);
  restarted.stamp_ns += kSecond;
  restarted.odometry_pose = readings_[1].odometry_pose;
  EXPECT_FALSE(session.AddReading(restarted).restarted);
  EXPECT_EQ(session.verifier().graph().num_poses(), 52);

  // Near the origin, and back there: no jump, no restart; nor with the test
  // off.
  for (const double restart_jump : {1.0, 0.0}) {
    RobotSessionOptions options = Options();
    options.restart_jump = restart_jump;
    RobotSession<Pose2> near(options, on_skip_);
    KeyframeRecord<Pose2> reading{kSecond, Pose2(), OdometryCovariance::Zero()};
    for (const Pose2& pose : {Pose2(), Pose2(0.5, 0.0, 0.0), Pose2()}) {
      reading.odometry_pose = pose;
      reading.stamp_ns += kSecond;
      EXPECT_FALSE(near.AddReading(reading).restarted);
    }
    reading.odometry_pose = before;
    reading.stamp_ns += kSecond;
    near.AddReading(reading);
    reading.odometry_pose = Pose2();
    reading.stamp_ns += kSecond;
    EXPECT_EQ(near.AddReading(reading).restarted, restart_jump > 0.0);
  }
}

TEST_F(RobotSessionTest, SkipsACandidateItCannotJudgeWithItsReason) {
  RobotSession<Pose2> session(Options(), on_skip_);
  Drive(&session, 0, 5);
  const Pose2 z;
  const auto information = Constraint<Pose2>::Information::Identity().eval();
  session.AddCandidate(7, 2, 2, z, information);
  session.AddCandidate(8, -1, 3, z, information);
  ASSERT_EQ(skipped_.size(), 2u);
  EXPECT_EQ(skipped_[0].message, 7);
  EXPECT_EQ(skipped_[0].defect, CandidateDefect::kSelfLoop);
  EXPECT_EQ(skipped_[1].message, 8);
  EXPECT_EQ(skipped_[1].defect, CandidateDefect::kUnknownPose);
  EXPECT_EQ(session.verifier().num_candidates(), 0);
}

TEST_F(RobotSessionTest, HoldsACandidateByStampUntilItsKeyframesExist) {
  RobotSession<Pose2> session(Options(), on_skip_);
  Drive(&session, 0, 10);
  const Pose2 z;
  const auto information = Constraint<Pose2>::Information::Identity().eval();
  // Keyframe 2 and keyframe 14 (not there yet), each stamped 10 ms off.
  session.AddCandidateByStamp(5, readings_[2].stamp_ns + 10'000'000,
                              readings_[14].stamp_ns - 10'000'000, z,
                              information);
  // Half-way between two keyframes, far from both: no keyframe is near.
  session.AddCandidateByStamp(6, readings_[3].stamp_ns + kSecond / 2,
                              readings_[8].stamp_ns, z, information);
  EXPECT_EQ(session.waiting_by_stamp(), 1);
  ASSERT_EQ(skipped_.size(), 1u);
  EXPECT_EQ(skipped_[0].message, 6);
  EXPECT_EQ(skipped_[0].defect, CandidateDefect::kUnknownPose);
  EXPECT_EQ(session.verifier().num_candidates(), 0);
  Drive(&session, 10, 16);
  EXPECT_EQ(session.waiting_by_stamp(), 0);
  ASSERT_EQ(session.verifier().num_candidates(), 1);
  EXPECT_EQ(session.verifier().ends_of(0),
            std::make_pair(PoseId{2}, PoseId{14}));
}

TEST_F(RobotSessionTest, OpenedAgainOnItsDatabaseItDecidesAsWithoutAStop) {
  const int n = world_.graph.num_poses();
  // A candidate by stamp that waits across the stop.
  const auto stamped = [&](RobotSession<Pose2>* session) {
    session->AddCandidateByStamp(99, readings_[3].stamp_ns,
                                 readings_[n - 1].stamp_ns, Pose2(),
                                 Constraint<Pose2>::Information::Identity());
    session->Update(false);
  };
  RobotSession<Pose2> straight(Options(), on_skip_);
  Drive(&straight, 0, n / 2);
  stamped(&straight);
  Drive(&straight, n / 2, n);
  straight.Update(true);

  const std::string database = dir_.File("session.db");
  {
    RobotSession<Pose2> first(Options(database), on_skip_);
    EXPECT_EQ(first.Resume().keyframes, 0);
    Drive(&first, 0, n / 2);
    stamped(&first);
  }
  RobotSession<Pose2> resumed(Options(database), on_skip_);
  const ResumeSummary summary = resumed.Resume();
  EXPECT_EQ(summary.keyframes, n / 2);
  EXPECT_GT(summary.checkpoint_update, 0);
  EXPECT_EQ(summary.differing_decisions, 0);
  EXPECT_EQ(resumed.waiting_by_stamp(), 1);
  // A bag played again from its start: what was taken is not taken twice.
  const auto again = resumed.AddReading(readings_[n / 2 - 1]);
  EXPECT_TRUE(again.already_recorded);
  EXPECT_FALSE(again.keyframe);
  Drive(&resumed, n / 2, n);
  resumed.Update(true);
  EXPECT_EQ(resumed.waiting_by_stamp(), 0);
  const OnlineVerifier<Pose2>& a = resumed.verifier();
  const OnlineVerifier<Pose2>& b = straight.verifier();
  ASSERT_EQ(a.num_candidates(), b.num_candidates());
  ASSERT_GT(a.num_in_state(LoopState::kAccepted), 0);
  for (int c = 0; c < a.num_candidates(); ++c) {
    EXPECT_EQ(a.ends_of(c), b.ends_of(c)) << "candidate " << c;
    EXPECT_EQ(a.state(c), b.state(c)) << "candidate " << c;
  }
  EXPECT_TRUE(skipped_.empty());
}

TEST_F(RobotSessionTest, AnUpdateItsDatabaseCannotRecordLosesNoInput) {
  const std::string database = dir_.File("session.db");
  std::vector<LoopState> states;
  {
    RobotSession<Pose2> session(Options(database), on_skip_);
    session.Resume();
    Drive(&session, 0, 100);
    // Another process holds the database's write lock: the next update
    // cannot be recorded (after SQLite's busy timeout), and the session says
    // so and goes on.
    sqlite3* other = nullptr;
    ASSERT_EQ(sqlite3_open(database.c_str(), &other), SQLITE_OK);
    ASSERT_EQ(sqlite3_exec(other, "BEGIN EXCLUSIVE", nullptr, nullptr, nullptr),
              SQLITE_OK);
    ASSERT_TRUE(session.AddReading(readings_[100]).keyframe);
    const auto blocked = session.Update(false);
    EXPECT_NE(blocked.store_error.find(database), std::string::npos)
        << blocked.store_error;
    sqlite3_exec(other, "ROLLBACK", nullptr, nullptr, nullptr);
    sqlite3_close(other);
    // The next update records what the blocked one could not.
    Drive(&session, 101, 150);
    for (int c = 0; c < session.verifier().num_candidates(); ++c) {
      states.push_back(session.verifier().state(c));
    }
  }
  RobotSession<Pose2> resumed(Options(database), on_skip_);
  EXPECT_EQ(resumed.Resume().keyframes, 150);
  ASSERT_EQ(resumed.verifier().num_candidates(),
            static_cast<int>(states.size()));
  for (int c = 0; c < resumed.verifier().num_candidates(); ++c) {
    EXPECT_EQ(resumed.verifier().state(c), states[c]) << "candidate " << c;
  }
}

TEST(RobotSession, RefusesOptionsThatDoNotValidate) {
  RobotSessionOptions options;
  options.odometry.odometry_information = {1.0, 1.0};
  EXPECT_THROW(RobotSession<Pose2>(options, nullptr), std::invalid_argument);
  options = RobotSessionOptions();
  options.odometry.keyframe_translation = -1.0;
  EXPECT_THROW(RobotSession<Pose2>(options, nullptr), std::invalid_argument);
  options = RobotSessionOptions();
  options.rrr.cluster_window = 0;
  EXPECT_THROW(RobotSession<Pose2>(options, nullptr), std::invalid_argument);
}

}  // namespace
}  // namespace rrr
