// A fleet's session database, as a FleetSession records and takes it up.
#include "rrr/session/fleet_store.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "../testing/chain_worlds.h"
#include "../testing/scratch_dir.h"
#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/session/fleet_session.h"
#include "sqlite_db.h"

namespace rrr {
namespace {

using ::testing::HasSubstr;

// Two robots of one world with false loops, the second starting at its pose
// 400 with its odometry at zero there; loops within and between them come
// once both ends exist.
class FleetStoreTest : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = dir_.File("fleet.db");
    WorldOptions world = testing::Grid(800, 5);
    world.false_loops = 40;
    world.group = 4;
    graph_ = SimulateWorld(world).graph;
    readings_ = {testing::Readings(graph_, 0, 399, 0),
                 testing::Readings(graph_, 400, 799, 0)};
  }

  static FleetOptions Options() {
    FleetOptions options;
    options.rrr = testing::ChainWorldOptions();
    options.restart_jump = 3.0;
    return options;
  }

  // Rounds [begin, end): each robot's reading of the round, then the loops
  // whose later end came in it (both ends fed, by the keyframe ids the
  // fleet gave them); an update after every tenth round (recorded if the
  // session has a database).
  void Drive(int begin, int end, FleetSession<Pose2>* session) {
    for (int k = begin; k < end; ++k) {
      for (int r = 0; r < 2; ++r) {
        const auto taken = session->AddReading(r, readings_[r][k]);
        ASSERT_TRUE(taken.keyframe);
        id_[r][k] = taken.id;
      }
      for (const auto& e : graph_.loops()) {
        const int ra = e.from < 400 ? 0 : 1, rb = e.to < 400 ? 0 : 1;
        const int ka = e.from % 400, kb = e.to % 400;
        if (std::max(ka, kb) != k || id_[ra][ka] < 0 || id_[rb][kb] < 0) {
          continue;
        }
        session->AddLoop(ra, id_[ra][ka], rb, id_[rb][kb], e.measurement,
                         e.information);
      }
      if (k % 10 == 9) {
        ASSERT_EQ(session->Update(false).store_error, "");
      }
    }
  }

  // A fleet of `robots` recorded in the test's database, taken up.
  std::unique_ptr<FleetSession<Pose2>> Open(
      const std::vector<std::string>& robots,
      FleetResumeSummary* summary = nullptr) {
    auto session =
        std::make_unique<FleetSession<Pose2>>(robots, Options(), path_);
    const FleetResumeSummary resumed = session->Resume();
    if (summary) *summary = resumed;
    return session;
  }

  static std::vector<LoopState> States(const Fleet<Pose2>& fleet) {
    std::vector<LoopState> states;
    for (int c = 0; c < fleet.verifier().num_candidates(); ++c) {
      states.push_back(fleet.verifier().state(c));
    }
    return states;
  }

  testing::ScratchDir dir_;
  std::string path_;
  PoseGraph<Pose2> graph_;
  std::vector<std::vector<KeyframeRecord<Pose2>>> readings_;
  // The keyframe id of each robot's reading of each round; -1: not taken.
  std::vector<std::vector<std::int64_t>> id_ =
      std::vector<std::vector<std::int64_t>>(
          2, std::vector<std::int64_t>(400, -1));
};

TEST_F(FleetStoreTest, AResumeAfterACrashHasEveryCommittedInputAndDecision) {
  std::vector<LoopState> at_last_commit;
  int keyframes = 0;
  {
    const auto session = Open({"a", "b"});
    Drive(0, 250, session.get());
    at_last_commit = States(session->fleet());
    keyframes = session->fleet().Graph().num_poses();
    Drive(250, 255, session.get());  // then the process dies
  }
  ASSERT_EQ(keyframes, 500);
  ASSERT_GT(at_last_commit.size(), 10u);

  FleetResumeSummary summary;
  const auto session = Open({"a", "b"}, &summary);
  const Fleet<Pose2>& fleet = session->fleet();
  EXPECT_EQ(summary.keyframes, 500);
  EXPECT_EQ(summary.sessions, 2);
  EXPECT_EQ(summary.updates, 25);
  EXPECT_EQ(summary.candidates, static_cast<int>(at_last_commit.size()));
  EXPECT_EQ(summary.differing_decisions, 0);
  EXPECT_EQ(States(fleet), at_last_commit);

  // The readings of rounds 250-254 never reached the fleet. Each robot
  // continues in a new session, joined to the old ones only by loops; its
  // keyframes count on.
  for (int r = 0; r < 2; ++r) {
    std::fill(id_[r].begin() + 250, id_[r].begin() + 255, -1);
    const auto taken = session->AddReading(r, readings_[r][255]);
    EXPECT_TRUE(taken.new_session);
    EXPECT_EQ(taken.id, 250);
    id_[r][255] = taken.id;
  }
  // The candidates of the rounds after it, but those naming a keyframe that
  // was lost.
  const int before = fleet.verifier().num_candidates();
  int fed = 0;
  for (const auto& e : graph_.loops()) {
    const int ka = e.from % 400, kb = e.to % 400;
    fed += std::max(ka, kb) >= 256 &&
           (std::min(ka, kb) < 250 || std::min(ka, kb) > 254);
  }
  Drive(256, 400, session.get());
  session->Update(true);
  EXPECT_EQ(fleet.verifier().num_candidates(), before + fed);
  EXPECT_EQ(fleet.sessions(0).size(), 2u);
  EXPECT_EQ(fleet.sessions(1).size(), 2u);
  EXPECT_EQ(fleet.Graph().odometry().size(), 2u * (249 + 144))
      << "no odometry across the crash (nor between the robots)";
}

TEST_F(FleetStoreTest, AResumeOfAFinishedRunDecidesAsTheRun) {
  std::vector<LoopState> finished;
  {
    const auto session = Open({"a", "b"});
    Drive(0, 400, session.get());
    // One candidate more, by the stamps of its keyframes (a's 390 and b's
    // 395, as a loop of the world would be measured).
    const Pose2 z = graph_.estimates()[390].between(graph_.estimates()[795]);
    const Eigen::Matrix3d information = graph_.loops()[0].information;
    const int next = session->fleet().verifier().num_candidates();
    EXPECT_EQ(
        session->AddLoopByStamp(0, readings_[0][390].stamp_ns, 1,
                                readings_[1][395].stamp_ns, z, information),
        next);
    EXPECT_EQ(session->Update(true).store_error, "");
    finished = States(session->fleet());
  }
  size_t accepted = 0, refused = 0;
  for (const LoopState s : finished) {
    accepted += s == LoopState::kAccepted;
    refused += s == LoopState::kRejected;
  }
  ASSERT_GT(accepted, 60u);
  ASSERT_GT(refused, 10u) << "the false loops";

  // The robots in another order, and one more: they are matched by name.
  FleetResumeSummary summary;
  const auto session = Open({"c", "b", "a"}, &summary);
  const Fleet<Pose2>& fleet = session->fleet();
  EXPECT_EQ(summary.differing_decisions, 0);
  EXPECT_EQ(States(fleet), finished);
  EXPECT_EQ(fleet.sessions(2).size(), 1u);
  EXPECT_EQ(fleet.sessions(1).size(), 1u);
  EXPECT_TRUE(fleet.sessions(0).empty());
}

TEST_F(FleetStoreTest, AResumeWithoutARecordedRobotSaysWhich) {
  {
    const auto session = Open({"a", "b"});
    Drive(0, 20, session.get());
  }
  try {
    Open({"a"});
    FAIL() << "resumed without robot b";
  } catch (const SessionError& e) {
    EXPECT_THAT(e.what(), HasSubstr(path_));
    EXPECT_THAT(e.what(), HasSubstr("robot 'b' is recorded but not among"));
  }
}

TEST_F(FleetStoreTest, ARecordThatDoesNotReplayAsRecordedIsRefusedNamingIt) {
  {
    const auto session = Open({"a", "b"});
    Drive(0, 100, session.get());
  }
  {  // a keyframe taken out of robot b's record
    SqliteDb db(path_, false);
    db.Execute(
        "DELETE FROM inputs WHERE seq = (SELECT min(seq) FROM inputs WHERE "
        "kind = 1 AND robot = 1 AND number = 50)");
  }
  try {
    Open({"a", "b"});
    FAIL() << "resumed";
  } catch (const SessionError& e) {
    EXPECT_THAT(e.what(), HasSubstr(path_));
    EXPECT_THAT(e.what(), HasSubstr("the keyframe of robot 'b' recorded as 51 "
                                    "arrives as 50"));
  }
}

TEST_F(FleetStoreTest, AFleetsDatabaseAndOneRobotsAreNotTakenForEachOther) {
  { FleetStore<Pose2> store(path_, {"a"}, "map"); }
  EXPECT_TRUE(IsFleetDatabase(path_));
  const auto fails_with = [](const auto& open, const std::string& problem) {
    try {
      open();
      ADD_FAILURE() << "opened";
    } catch (const SessionError& e) {
      EXPECT_THAT(e.what(), HasSubstr(problem));
    }
  };
  fails_with([&] { SessionStore<Pose2>(path_, "map"); },
             "a fleet's session database");
  fails_with([&] { ReadSession(path_); }, "a fleet's session database");
  fails_with([&] { FleetStore<Pose3>(path_, {"a"}, "map"); }, "2D fleet");
  fails_with([&] { FleetStore<Pose2>(path_, {"a"}, "published"); },
             "recorded with the map procedure");

  const std::string single = dir_.File("robot.db");
  { SessionStore<Pose2> store(single, "map"); }
  EXPECT_FALSE(IsFleetDatabase(single));
  fails_with([&] { FleetStore<Pose2>(single, {"a"}, "map"); },
             "not a fleet's session database");
}

}  // namespace
}  // namespace rrr
