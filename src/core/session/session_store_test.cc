// The session database, as a Session records and takes it up: a resumed
// session decides as one that never stopped, a crash loses only the
// unfinished update, and a database that cannot be resumed is refused with
// the file and the reason.
#include "rrr/session/session_store.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "../testing/chain_worlds.h"
#include "../testing/scratch_dir.h"
#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/session/session.h"
#include "session_codec.h"
#include "sqlite_db.h"

namespace rrr {
namespace {

using ::testing::HasSubstr;

// Runs `sql` on the database at `path`.
void Tamper(const std::string& path, const std::string& sql) {
  SqliteDb db(path, false);
  db.Execute(sql);
}

// The message of the SessionError that `open` throws, or "" if none.
template <class Open>
std::string ErrorOf(const Open& open) {
  try {
    open();
  } catch (const SessionError& e) {
    return e.what();
  }
  return "";
}

std::vector<LoopState> States(const OnlineVerifier<Pose2>& verifier) {
  std::vector<LoopState> states;
  for (int c = 0; c < verifier.num_candidates(); ++c) {
    states.push_back(verifier.state(c));
  }
  return states;
}

// Two robots of one world with false loops, the second starting at its pose
// 400 with its odometry at zero there; loops within and between them come
// once both ends exist.
class SessionStoreTest : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = dir_.File("session.db");
    WorldOptions world = testing::Grid(800, 5);
    world.false_loops = 40;
    world.group = 4;
    graph_ = SimulateWorld(world).graph;
    readings_ = {testing::Readings(graph_, 0, 399, 0),
                 testing::Readings(graph_, 400, 799, 0)};
  }

  SessionOptions Options(const std::string& database,
                         int checkpoint_keyframes = 100) const {
    SessionOptions options;
    options.rrr = testing::ChainWorldOptions();
    options.database = database;
    options.checkpoint_keyframes = checkpoint_keyframes;
    return options;
  }

  // Rounds [begin, end): each robot's reading of the round, then the loops
  // whose later end came in it (by the keyframe ids the session gave them);
  // an update after every tenth round. The session's robots are the first
  // of the two.
  void Drive(int begin, int end, Session<Pose2>* session) {
    const int robots = static_cast<int>(session->robots().size());
    for (int k = begin; k < end; ++k) {
      for (int r = 0; r < robots; ++r) {
        const auto taken = session->AddReading(r, readings_[r][k]);
        ASSERT_TRUE(taken.keyframe) << taken.problem;
        id_[r][k] = taken.id;
      }
      for (const auto& e : graph_.loops()) {
        const int ra = e.from < 400 ? 0 : 1, rb = e.to < 400 ? 0 : 1;
        const int ka = e.from % 400, kb = e.to % 400;
        if (std::max(ka, kb) != k || ra >= robots || rb >= robots ||
            id_[ra][ka] < 0 || id_[rb][kb] < 0) {
          continue;
        }
        session->AddCandidate(0, ra, id_[ra][ka], rb, id_[rb][kb],
                              e.measurement, e.information);
      }
      if (k % 10 == 9) {
        ASSERT_EQ(session->Update(false).store_error, "");
      }
    }
  }

  // A session of `robots` on the test's database, taken up.
  std::unique_ptr<Session<Pose2>> Open(const std::vector<std::string>& robots,
                                       ResumeSummary* summary = nullptr,
                                       int checkpoint_keyframes = 100) {
    auto session = std::make_unique<Session<Pose2>>(
        robots, Options(path_, checkpoint_keyframes), nullptr);
    const ResumeSummary resumed = session->Resume();
    if (summary) *summary = resumed;
    return session;
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

TEST_F(SessionStoreTest, OneRobotOpenedAgainDecidesAsWithoutAStop) {
  // A candidate by stamp that waits across the stop.
  const auto stamped = [&](Session<Pose2>* session) {
    session->AddCandidateByStamp(99, 0, readings_[0][3].stamp_ns, 0,
                                 readings_[0][399].stamp_ns, Pose2(),
                                 Pose2::Jacobian::Identity());
  };
  Session<Pose2> straight({""}, Options(""), nullptr);
  Drive(0, 200, &straight);
  stamped(&straight);
  Drive(200, 400, &straight);
  straight.Update(true);

  {
    const auto first = Open({""});
    Drive(0, 200, first.get());
    stamped(first.get());
    first->Update(false);
  }
  ResumeSummary summary;
  const auto resumed = Open({""}, &summary);
  EXPECT_EQ(summary.keyframes, 200);
  EXPECT_EQ(summary.sessions, 1);
  EXPECT_GT(summary.checkpoint_update, 0);
  EXPECT_EQ(summary.differing_decisions, 0);
  EXPECT_EQ(resumed->num_waiting_by_stamp(), 1);
  // A bag played again from its start: what was taken is not taken twice.
  for (const int k : {0, 199}) {
    const auto again = resumed->AddReading(0, readings_[0][k]);
    EXPECT_TRUE(again.already_recorded);
    EXPECT_FALSE(again.keyframe);
  }
  Drive(200, 400, resumed.get());
  resumed->Update(true);
  EXPECT_EQ(resumed->num_waiting_by_stamp(), 0);
  EXPECT_EQ(resumed->num_chains(), 1) << "the session continued";
  ASSERT_GT(resumed->verifier().num_in_state(LoopState::kAccepted), 0);
  ASSERT_EQ(resumed->verifier().num_candidates(),
            straight.verifier().num_candidates());
  for (int c = 0; c < straight.verifier().num_candidates(); ++c) {
    EXPECT_EQ(resumed->from(c).id, straight.from(c).id) << c;
    EXPECT_EQ(resumed->to(c).id, straight.to(c).id) << c;
  }
  EXPECT_EQ(States(resumed->verifier()), States(straight.verifier()));
}

TEST_F(SessionStoreTest, AFleetResumedAfterACrashHasEveryCommittedInput) {
  std::vector<LoopState> at_last_commit;
  {
    const auto session = Open({"a", "b"});
    Drive(0, 250, session.get());
    at_last_commit = States(session->verifier());
    Drive(250, 255, session.get());  // then the process dies
  }
  ASSERT_GT(at_last_commit.size(), 10u);

  ResumeSummary summary;
  const auto session = Open({"a", "b"}, &summary);
  EXPECT_EQ(summary.keyframes, 500);
  EXPECT_EQ(summary.sessions, 2);
  EXPECT_EQ(summary.updates, 25);
  EXPECT_EQ(summary.candidates, static_cast<int>(at_last_commit.size()));
  EXPECT_GT(summary.checkpoint_update, 0) << "a fleet resumes from it too";
  EXPECT_EQ(summary.differing_decisions, 0);
  EXPECT_EQ(States(session->verifier()), at_last_commit);

  // The readings of rounds 250-254 never reached the database: each robot's
  // session goes on from its last recorded keyframe, its ids counting on.
  for (int r = 0; r < 2; ++r) {
    std::fill(id_[r].begin() + 250, id_[r].begin() + 255, -1);
    const auto taken = session->AddReading(r, readings_[r][255]);
    EXPECT_FALSE(taken.new_session);
    EXPECT_EQ(taken.id, 250);
    id_[r][255] = taken.id;
  }
  Drive(256, 400, session.get());
  session->Update(true);
  EXPECT_EQ(session->num_chains(), 2);
  EXPECT_EQ(session->MapOfRobot(1), 0);
  EXPECT_EQ(session->Graph().odometry().size(), 2u * 394);
}

TEST_F(SessionStoreTest, AFleetResumesFromItsCheckpointAsIfEveryUpdateHadRun) {
  Session<Pose2> straight({"a", "b"}, Options(""), nullptr);
  Drive(0, 400, &straight);
  straight.Update(true);
  {
    const auto session = Open({"a", "b"}, nullptr, 150);
    Drive(0, 300, session.get());
  }
  ResumeSummary summary;
  const auto resumed = Open({"a", "b"}, &summary, 150);
  // A checkpoint came with each commit that brought 150 keyframes or more
  // since the last (75 rounds, 8 updates): the last with update 24, after
  // round 239; the updates after it ran again.
  EXPECT_EQ(summary.checkpoint_update, 24);
  EXPECT_FALSE(summary.checkpoint_of_other_options);
  EXPECT_EQ(summary.updates, 30);
  EXPECT_EQ(summary.differing_decisions, 0);
  Drive(300, 400, resumed.get());
  resumed->Update(true);
  EXPECT_EQ(States(resumed->verifier()), States(straight.verifier()));
  EXPECT_GT(straight.verifier().num_in_state(LoopState::kRejected), 10)
      << "the false loops";
}

TEST_F(SessionStoreTest, RunsEveryUpdateAgainWhenTheOptionsChanged) {
  { Drive(0, 200, Open({"a", "b"}).get()); }
  SessionOptions other = Options(path_);
  other.rrr.noise_margin = 4.0;
  Session<Pose2> resumed({"a", "b"}, other, nullptr);
  const ResumeSummary summary = resumed.Resume();
  EXPECT_TRUE(summary.checkpoint_of_other_options);
  EXPECT_EQ(summary.checkpoint_update, 0);
  EXPECT_EQ(summary.updates, 20);
  other.database.clear();
  Session<Pose2> reference({"a", "b"}, other, nullptr);
  Drive(0, 200, &reference);
  EXPECT_EQ(States(resumed.verifier()), States(reference.verifier()));
}

TEST_F(SessionStoreTest, AResumeMatchesRobotsByNameAndSaysWhichIsMissing) {
  std::vector<LoopState> finished;
  {
    const auto session = Open({"a", "b"});
    Drive(0, 100, session.get());
    session->Update(true);
    finished = States(session->verifier());
  }
  ResumeSummary summary;
  const auto session = Open({"c", "b", "a"}, &summary);
  EXPECT_EQ(summary.differing_decisions, 0);
  EXPECT_EQ(States(session->verifier()), finished);
  EXPECT_EQ(session->sessions(2).size(), 1u);
  EXPECT_EQ(session->sessions(1).size(), 1u);
  EXPECT_TRUE(session->sessions(0).empty());
  EXPECT_EQ(ReadSessionDatabase(path_).robots,
            (std::vector<std::string>{"a", "b", "c"}));
  const std::string error = ErrorOf([&] { Open({"a"}); });
  EXPECT_THAT(error, HasSubstr(path_));
  EXPECT_THAT(error, HasSubstr("robot 'b' is recorded but not among"));
}

TEST_F(SessionStoreTest, AnUpdateItsDatabaseCannotRecordLosesNoInput) {
  std::vector<LoopState> states;
  {
    const auto session = Open({"a", "b"});
    Drive(0, 100, session.get());
    // Another process holds the database's write lock: the next update
    // cannot be recorded (after SQLite's busy timeout), and the session says
    // so and goes on.
    sqlite3* other = nullptr;
    ASSERT_EQ(sqlite3_open(path_.c_str(), &other), SQLITE_OK);
    ASSERT_EQ(sqlite3_exec(other, "BEGIN EXCLUSIVE", nullptr, nullptr, nullptr),
              SQLITE_OK);
    ASSERT_TRUE(session->AddReading(0, readings_[0][100]).keyframe);
    const auto blocked = session->Update(false);
    EXPECT_THAT(blocked.store_error, HasSubstr(path_));
    sqlite3_exec(other, "ROLLBACK", nullptr, nullptr, nullptr);
    sqlite3_close(other);
    // The next update records what the blocked one could not.
    ASSERT_TRUE(session->AddReading(1, readings_[1][100]).keyframe);
    Drive(101, 150, session.get());
    states = States(session->verifier());
  }
  ResumeSummary summary;
  const auto resumed = Open({"a", "b"}, &summary);
  EXPECT_EQ(summary.keyframes, 300);
  EXPECT_EQ(States(resumed->verifier()), states);
}

TEST_F(SessionStoreTest, ARecordThatDoesNotReplayAsRecordedIsRefusedNamingIt) {
  { Drive(0, 100, Open({"a", "b"}).get()); }
  // A keyframe taken out of robot b's record.
  Tamper(path_,
         "DELETE FROM inputs WHERE seq = (SELECT min(seq) FROM inputs WHERE "
         "kind = 1 AND robot = 1 AND number = 50)");
  const std::string error = ErrorOf([&] { Open({"a", "b"}); });
  EXPECT_THAT(error, HasSubstr(path_));
  EXPECT_THAT(error, HasSubstr("the keyframe of robot 'b' recorded as 51 "
                               "arrives as 50"));
}

TEST_F(SessionStoreTest, RecordsTheOptionsItsDecisionsWereMadeUnder) {
  { Drive(0, 20, Open({"a"}).get()); }
  const SessionDatabase recorded = ReadSessionDatabase(path_);
  const RrrOptions given = Options(path_).rrr;
  EXPECT_EQ(OptionsText(recorded.options), OptionsText(given));
  EXPECT_EQ(recorded.options.cluster_window, given.cluster_window);
  EXPECT_EQ(recorded.options.alpha, given.alpha);
  Tamper(path_,
         "UPDATE meta SET value = 'cluster_window=50 windy=1' "
         "WHERE key = 'options'");
  const std::string error = ErrorOf([&] { ReadSessionDatabase(path_); });
  EXPECT_THAT(error, HasSubstr(path_));
  EXPECT_THAT(error, HasSubstr("unknown option windy"));
  Tamper(path_,
         "UPDATE meta SET value = 'cluster_window=0' "
         "WHERE key = 'options'");
  EXPECT_THAT(ErrorOf([&] { ReadSessionDatabase(path_); }),
              HasSubstr("cluster_window must be at least 1"));
}

TEST_F(SessionStoreTest, RefusesWhatItCannotResume) {
  { Drive(0, 100, Open({"a", "b"}, nullptr, 50).get()); }
  EXPECT_THAT(
      ErrorOf([&] { SessionStore<Pose3>(path_, {"a"}, RrrOptions(), 0); }),
      HasSubstr("2D session, but this verifier is 3D"));
  EXPECT_THAT(ErrorOf([&] {
                RrrOptions published;
                published.procedure = Procedure::kPublished;
                SessionStore<Pose2>(path_, {"a"}, published, 0);
              }),
              HasSubstr("recorded with the map procedure"));
  // A checkpoint that is not one, and rows that are not inputs.
  Tamper(path_, "UPDATE checkpoint SET state = x'00'");
  EXPECT_THAT(ErrorOf([&] {
                Open({"a", "b"});
              }),
              HasSubstr("the checkpoint after update 9: "));
  Tamper(path_, "DELETE FROM checkpoint");
  Tamper(path_, "UPDATE inputs SET information = x'00' WHERE seq = 5");
  EXPECT_THAT(ErrorOf([&] {
                Open({"a", "b"});
              }),
              HasSubstr("input 5: an information matrix holds 1 bytes"));
  Tamper(path_, "UPDATE inputs SET kind = 7 WHERE seq = 5");
  EXPECT_THAT(ErrorOf([&] {
                Open({"a", "b"});
              }),
              HasSubstr("input 5: unknown kind 7"));
  // Databases of other versions, and files that are none.
  Tamper(path_, "UPDATE meta SET value = '3' WHERE key = 'schema_version'");
  const std::string version = ErrorOf([&] { ReadSessionDatabase(path_); });
  EXPECT_EQ(version.rfind(path_, 0), 0u) << version;
  EXPECT_THAT(version, HasSubstr("schema version 3, but this rrr reads "
                                 "version 4"));
  Tamper(path_,
         "INSERT INTO meta(key, value) VALUES ('fleet_schema_version', '1')");
  EXPECT_THAT(ErrorOf([&] {
                Open({"a", "b"});
              }),
              HasSubstr("a fleet's database of schema version 1"));
  const std::string text = dir_.File("graph.g2o");
  std::ofstream(text) << "VERTEX_SE2 0 0 0 0\n";
  EXPECT_THAT(ErrorOf([&] { ReadSessionDatabase(text); }), HasSubstr(text));
  EXPECT_FALSE(LooksLikeSessionDatabase(text));
  EXPECT_TRUE(LooksLikeSessionDatabase(path_));
  EXPECT_THAT(ErrorOf([&] { ReadSessionDatabase(dir_.File("none.db")); }),
              HasSubstr("cannot be opened"));
}

TEST(SessionCodec, StoresASymmetricMatrixAsItsUpperTriangle) {
  Eigen::Matrix3d symmetric;
  symmetric << 4, 1, 0.5, 1, 3, 0.25, 0.5, 0.25, 2;
  const std::vector<double> upper = Encode(symmetric);
  EXPECT_EQ(upper, (std::vector<double>{4, 1, 0.5, 3, 0.25, 2}));
  Eigen::Matrix3d lopsided = symmetric;
  lopsided(2, 0) = 0.5 + 1e-16;
  EXPECT_EQ(Encode(lopsided).size(), 9u);  // kept whole, not symmetrized
}

TEST_F(SessionStoreTest, StoresSymmetricMatricesHalf) {
  { Drive(0, 40, Open({"a"}).get()); }
  SqliteDb db(path_, false);
  SqliteStatement longest(&db,
                          "SELECT max(length(covariance)), "
                          "max(length(information)) FROM inputs");
  ASSERT_TRUE(longest.Step());
  // 6 x 6 covariance: 21 numbers, not 36; 3 x 3 information: 6, not 9.
  EXPECT_EQ(longest.Int(0), 21 * 8);
  EXPECT_EQ(longest.Int(1), 6 * 8);
}

}  // namespace
}  // namespace rrr
