// The session database: a recorded run resumes with the same decisions, a
// crash loses only the unfinished update, and a database that cannot be
// resumed is refused with the file and the reason.
#include "rrr/session/session_store.h"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <cstdio>
#include <fstream>
#include <stdexcept>

#include "../testing/replay.h"
#include "../testing/scratch_dir.h"
#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/rrr/map/map_verifier.h"
#include "rrr/sim/simulated_world.h"
#include "session_codec.h"

namespace rrr {
namespace {

class SessionStoreTest : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = dir_.File("session.db");
    WorldOptions options;
    options.poses = 700;
    options.false_loops = 20;
    options.group = 2;
    world_ = SimulateWorld(options);
  }

  // Feeds the world's poses from `first` to `poses` - 1 (and the candidates
  // that have both poses by then) to `verifier` and `store` as the node
  // does: an update after every `update_every` poses, each committed with
  // the verifier (for checkpoints).
  void Record(MapVerifier<Pose2>* verifier, SessionStore<Pose2>* store,
              int poses, int update_every, bool commit_last = true,
              int first = 0) {
    const auto& g = world_.graph;
    std::vector<std::vector<int>> loops_at(g.num_poses());
    for (size_t k = 0; k < g.loops().size(); ++k) {
      const auto& l = g.loops()[k];
      loops_at[std::max(l.from, l.to)].push_back(static_cast<int>(k));
    }
    for (int p = first; p < poses; ++p) {
      KeyframeRecord<Pose2> keyframe;
      keyframe.stamp_ns = 1000000000LL * p;
      keyframe.odometry_pose = g.estimates()[p];
      keyframe.covariance(0, 0) = p;
      if (p == 0) {
        verifier->AddFirstPose(g.ids()[0], g.estimates()[0]);
        store->RecordFirstKeyframe(g.ids()[0], keyframe);
      } else {
        const auto& odometry = g.odometry()[p - 1];
        const PoseId id =
            verifier->AddOdometry(odometry.measurement, odometry.information);
        store->RecordKeyframe(id, keyframe, odometry.measurement,
                              odometry.information);
      }
      for (const int k : loops_at[p]) {
        const auto& l = g.loops()[k];
        const int number = verifier->AddLoop(g.ids()[l.from], g.ids()[l.to],
                                             l.measurement, l.information);
        store->RecordCandidate(number, g.ids()[l.from], g.ids()[l.to],
                               l.measurement, l.information);
      }
      const bool last = p + 1 == poses;
      if ((p + 1) % update_every == 0 || last) {
        const auto changes = verifier->Update();
        if (!last || commit_last) {
          store->CommitUpdate(false, changes, verifier);
        }
      }
    }
  }

  // Records the world's first `poses` poses into a new session database at
  // path_, an update committed every 10, and closes it.
  void RecordFirstPoses(int poses) {
    MapVerifier<Pose2> verifier{RrrOptions()};
    SessionStore<Pose2> store(path_, "map");
    Record(&verifier, &store, poses, 10);
  }

  testing::ScratchDir dir_;
  std::string path_;
  SimulatedWorld world_;
};

std::vector<LoopState> States(const OnlineVerifier<Pose2>& verifier) {
  std::vector<LoopState> states;
  states.reserve(verifier.num_candidates());
  for (int c = 0; c < verifier.num_candidates(); ++c) {
    states.push_back(verifier.state(c));
  }
  return states;
}

TEST_F(SessionStoreTest, ResumesWithTheSameDecisionsAndKeyframes) {
  MapVerifier<Pose2> original{RrrOptions()};
  {
    SessionStore<Pose2> store(path_, "map");
    Record(&original, &store, world_.graph.num_poses(), 7);
    const auto changes = original.Finish();
    store.CommitUpdate(true, changes);
  }
  MapVerifier<Pose2> resumed{RrrOptions()};
  SessionStore<Pose2> store(path_, "map");
  std::vector<KeyframeRecord<Pose2>> keyframes;
  const ResumeSummary summary =
      store.Resume(&resumed, [&](PoseId id, const KeyframeRecord<Pose2>& k) {
        EXPECT_EQ(id, static_cast<PoseId>(keyframes.size()));
        keyframes.push_back(k);
      });
  EXPECT_EQ(summary.keyframes, world_.graph.num_poses());
  EXPECT_EQ(summary.candidates, original.num_candidates());
  EXPECT_EQ(summary.updates, (world_.graph.num_poses() + 6) / 7 + 1);
  EXPECT_EQ(summary.differing_decisions, 0);
  EXPECT_EQ(States(resumed), States(original));
  ASSERT_EQ(keyframes.size(), static_cast<size_t>(world_.graph.num_poses()));
  EXPECT_EQ(keyframes[5].stamp_ns, 5000000000LL);
  EXPECT_EQ(keyframes[5].covariance(0, 0), 5.0);
  EXPECT_EQ(keyframes[5].odometry_pose.x(), world_.graph.estimates()[5].x());
  EXPECT_GT(original.AcceptedLoops().size(), 0u);
}

TEST_F(SessionStoreTest, ACrashLosesOnlyTheUnfinishedUpdate) {
  const int poses = 400;
  {
    MapVerifier<Pose2> verifier{RrrOptions()};
    SessionStore<Pose2> store(path_, "map");
    Record(&verifier, &store, poses, 10, /*commit_last=*/false);
    EXPECT_GT(store.num_uncommitted(), 0);
  }  // gone before its last commit, as after kill -9
  MapVerifier<Pose2> resumed{RrrOptions()};
  SessionStore<Pose2> store(path_, "map");
  const ResumeSummary summary = store.Resume(&resumed, nullptr);
  // The last update (poses 390..399) never committed.
  EXPECT_EQ(summary.keyframes, poses - 10);
  EXPECT_EQ(resumed.graph().num_poses(), summary.keyframes);
  EXPECT_EQ(summary.differing_decisions, 0);
  // Recording goes on where the database ends, and resumes again.
  MapVerifier<Pose2> reference{RrrOptions()};
  {
    SessionStore<Pose2> fresh(dir_.File("reference.db"), "map");
    Record(&reference, &fresh, summary.keyframes, 10);
  }
  EXPECT_EQ(States(resumed), States(reference));
}

TEST_F(SessionStoreTest, ReadSessionGivesTheGraphAndTheLastStates) {
  MapVerifier<Pose2> verifier{RrrOptions()};
  {
    SessionStore<Pose2> store(path_, "map");
    Record(&verifier, &store, world_.graph.num_poses(), 50);
    store.CommitUpdate(true, verifier.Finish());
  }
  const SessionContents contents = ReadSession(path_);
  const auto& graph = std::get<PoseGraph2>(contents.graph);
  EXPECT_EQ(contents.procedure, "map");
  EXPECT_EQ(graph.num_poses(), world_.graph.num_poses());
  EXPECT_EQ(graph.loops().size(), world_.graph.loops().size());
  EXPECT_EQ(graph.odometry().size(), world_.graph.odometry().size());
  ASSERT_EQ(contents.loop_states.size(), graph.loops().size());
  for (int c = 0; c < verifier.num_candidates(); ++c) {
    EXPECT_EQ(contents.loop_states[verifier.loop_of(c)], verifier.state(c));
  }
  EXPECT_TRUE(LooksLikeSessionDatabase(path_));
}

// Runs `sql` on the database at `path`.
void Tamper(const std::string& path, const std::string& sql) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(db, sql.c_str(), nullptr, nullptr, nullptr),
            SQLITE_OK);
  sqlite3_close(db);
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

TEST(SessionCodec, StoresASymmetricMatrixAsItsUpperTriangle) {
  Eigen::Matrix3d symmetric;
  symmetric << 4, 1, 0.5, 1, 3, 0.25, 0.5, 0.25, 2;
  const std::vector<double> upper = Encode(symmetric);
  EXPECT_EQ(upper, (std::vector<double>{4, 1, 0.5, 3, 0.25, 2}));
  Eigen::Matrix3d lopsided = symmetric;
  lopsided(2, 0) = 0.5 + 1e-16;
  EXPECT_EQ(Encode(lopsided).size(), 9u);  // kept whole, not symmetrized
}

TEST_F(SessionStoreTest, StoresSymmetricMatricesHalfAndReadsBothForms) {
  MapVerifier<Pose2> original{RrrOptions()};
  {
    SessionStore<Pose2> store(path_, "map");
    Record(&original, &store, 40, 10);
  }
  const auto bytes = [&](const std::string& sql) {
    sqlite3* db = nullptr;
    sqlite3_open(path_.c_str(), &db);
    sqlite3_stmt* statement = nullptr;
    sqlite3_prepare_v2(db, sql.c_str(), -1, &statement, nullptr);
    sqlite3_step(statement);
    const int n = sqlite3_column_int(statement, 0);
    sqlite3_finalize(statement);
    sqlite3_close(db);
    return n;
  };
  // 6 x 6 covariance: 21 numbers, not 36; 3 x 3 information: 6, not 9.
  EXPECT_EQ(bytes("SELECT max(length(covariance)) FROM inputs"), 21 * 8);
  EXPECT_EQ(bytes("SELECT max(length(information)) FROM inputs"), 6 * 8);
  // A database written whole (as before) reads the same.
  Tamper(path_,
         "UPDATE inputs SET covariance = zeroblob(288) WHERE pose_id = 7");
  MapVerifier<Pose2> resumed{RrrOptions()};
  std::vector<KeyframeRecord<Pose2>> keyframes;
  SessionStore<Pose2>(path_, "map")
      .Resume(&resumed, [&](PoseId, const KeyframeRecord<Pose2>& k) {
        keyframes.push_back(k);
      });
  ASSERT_EQ(keyframes.size(), 40u);
  EXPECT_EQ(keyframes[6].covariance(0, 0), 6.0);
  EXPECT_EQ(keyframes[7].covariance, OdometryCovariance::Zero());
  EXPECT_EQ(States(resumed), States(original));
  // Any other length is refused, naming the input.
  Tamper(path_,
         "UPDATE inputs SET covariance = zeroblob(80) WHERE pose_id = 9");
  EXPECT_NE(ErrorOf([&] {
              MapVerifier<Pose2> again{RrrOptions()};
              SessionStore<Pose2>(path_, "map")
                  .Resume(&again, [](PoseId, const KeyframeRecord<Pose2>&) {});
            }).find("a covariance holds 80 bytes, not 21 or 36 numbers"),
            std::string::npos);
}

TEST_F(SessionStoreTest, RefusesWhatItCannotResume) {
  { SessionStore<Pose2> store(path_, "map"); }
  const auto open2 = [&] { SessionStore<Pose2> store(path_, "map"); };
  EXPECT_NE(ErrorOf([&] {
              SessionStore<Pose3> store(path_, "map");
            }).find("2D session, but this verifier is 3D"),
            std::string::npos);
  EXPECT_NE(ErrorOf([&] {
              SessionStore<Pose2> store(path_, "published");
            }).find("recorded with the map procedure"),
            std::string::npos);
  Tamper(path_, "UPDATE meta SET value = '99' WHERE key = 'schema_version'");
  const std::string version = ErrorOf(open2);
  EXPECT_EQ(version.rfind(path_, 0), 0u) << version;
  EXPECT_NE(version.find("schema version 99"), std::string::npos) << version;

  const std::string text = dir_.File("graph.g2o");
  std::ofstream(text) << "VERTEX_SE2 0 0 0 0\n";
  EXPECT_NE(ErrorOf([&] { ReadSession(text); }).find(text), std::string::npos);
  EXPECT_FALSE(LooksLikeSessionDatabase(text));
  EXPECT_NE(ErrorOf([&] {
              ReadSession(dir_.File("none.db"));
            }).find("cannot be opened"),
            std::string::npos);
}

TEST_F(SessionStoreTest, RefusesRowsThatAreNotInputs) {
  RecordFirstPoses(100);
  Tamper(path_, "UPDATE inputs SET information = x'00' WHERE seq = 5");
  EXPECT_NE(ErrorOf([&] { ReadSession(path_); }).find("holds 1 bytes"),
            std::string::npos);
  Tamper(path_, "UPDATE inputs SET information = NULL, kind = 7 WHERE seq = 5");
  EXPECT_NE(ErrorOf([&] { ReadSession(path_); }).find("input 5: unknown kind"),
            std::string::npos);
  MapVerifier<Pose2> resumed{RrrOptions()};
  SessionStore<Pose2> store(path_, "map");
  EXPECT_NE(
      ErrorOf([&] { store.Resume(&resumed, nullptr); }).find("unknown kind 7"),
      std::string::npos);
}

TEST_F(SessionStoreTest, RefusesKeyframesThatGoBackInTime) {
  RecordFirstPoses(100);
  Tamper(path_,
         "UPDATE inputs SET stamp_ns = 0 WHERE seq = (SELECT MAX(seq) FROM "
         "inputs WHERE pose_id = 50)");
  MapVerifier<Pose2> resumed{RrrOptions()};
  SessionStore<Pose2> store(path_, "map");
  const std::string error = ErrorOf([&] { store.Resume(&resumed, nullptr); });
  EXPECT_EQ(error.rfind(path_, 0), 0u) << error;
  EXPECT_NE(error.find("keyframe 50 is stamped before"), std::string::npos)
      << error;
}

TEST_F(SessionStoreTest, NamesTheInputAKeyframeCallbackRefuses) {
  RecordFirstPoses(100);
  MapVerifier<Pose2> resumed{RrrOptions()};
  SessionStore<Pose2> store(path_, "map");
  const std::string error = ErrorOf([&] {
    store.Resume(&resumed, [](PoseId id, const KeyframeRecord<Pose2>&) {
      if (id == 30) throw std::invalid_argument("keyframe 30: not wanted");
    });
  });
  EXPECT_EQ(error.rfind(path_, 0), 0u) << error;
  EXPECT_NE(error.find(": keyframe 30: not wanted"), std::string::npos)
      << error;
}

TEST_F(SessionStoreTest, KeepsTheCandidatesWaitingByStampAtEachCommit) {
  Pose2::Jacobian information = Pose2::Jacobian::Identity() * 4.0;
  information(0, 1) = information(1, 0) = 1.0;
  std::int64_t first, second, third;
  {
    MapVerifier<Pose2> verifier{RrrOptions()};
    SessionStore<Pose2> store(path_, "map");
    Record(&verifier, &store, 50, 10);
    first =
        store.RecordStampedWaiting(7, 70, 80, Pose2(1, 2, 0.3), information);
    second =
        store.RecordStampedWaiting(9, 90, 95, Pose2(4, 5, 0.6), information);
    store.CommitUpdate(false, {});
    store.RecordStampedResolved(first);
    store.CommitUpdate(false, {});
    // Held and released again before a commit: never written.
    store.RecordStampedResolved(
        store.RecordStampedWaiting(0, 1, 2, Pose2(), information));
    store.CommitUpdate(false, {});
    // Not committed, as if the node were killed: lost, as the update is.
    third = store.RecordStampedWaiting(10, 100, 110, Pose2(), information);
    store.RecordStampedResolved(second);
    EXPECT_EQ(store.num_uncommitted(), 2);
  }
  EXPECT_LT(first, second);
  EXPECT_LT(second, third);
  MapVerifier<Pose2> resumed{RrrOptions()};
  SessionStore<Pose2> store(path_, "map");
  std::vector<StampedWaiting<Pose2>> held;
  const ResumeSummary summary =
      store.Resume(&resumed, nullptr,
                   [&](const StampedWaiting<Pose2>& w) { held.push_back(w); });
  EXPECT_EQ(summary.waiting_by_stamp, 1);
  ASSERT_EQ(held.size(), 1u);
  EXPECT_EQ(held[0].key, second);
  EXPECT_EQ(held[0].message, 9);
  EXPECT_EQ(held[0].from_ns, 90);
  EXPECT_EQ(held[0].to_ns, 95);
  EXPECT_EQ(held[0].measurement.Log(), Pose2(4, 5, 0.6).Log());
  EXPECT_EQ(held[0].information, information);
  // Keys go on above every key recorded before.
  EXPECT_GT(store.RecordStampedWaiting(0, 1, 2, Pose2(), information), second);
  EXPECT_EQ(ReadSession(path_).waiting_by_stamp, 1);
}

TEST_F(SessionStoreTest, BringsAVersionOneDatabaseUpToDate) {
  RecordFirstPoses(100);
  // As version 1 wrote it: no table of candidates waiting by stamp.
  Tamper(path_,
         "DROP TABLE waiting_by_stamp; UPDATE meta SET value = '1' WHERE key "
         "= 'schema_version'");
  EXPECT_EQ(std::get<PoseGraph2>(ReadSession(path_).graph).num_poses(), 100);
  MapVerifier<Pose2> resumed{RrrOptions()};
  {
    SessionStore<Pose2> store(path_, "map");
    const ResumeSummary summary = store.Resume(&resumed, nullptr);
    EXPECT_EQ(summary.keyframes, 100);
    EXPECT_EQ(summary.waiting_by_stamp, 0);
    store.RecordStampedWaiting(0, 1, 2, Pose2(), Pose2::Jacobian::Identity());
    store.CommitUpdate(false, {});
  }
  EXPECT_EQ(ReadSession(path_).waiting_by_stamp, 1);
  // Missing the table, a database of this version is not a session's.
  Tamper(path_, "DROP TABLE waiting_by_stamp");
  EXPECT_NE(ErrorOf([&] {
              ReadSession(path_);
            }).find("it is not a session database of rrr"),
            std::string::npos);
}

TEST_F(SessionStoreTest, ResumesFromTheCheckpointAsIfEveryUpdateHadRun) {
  MapVerifier<Pose2> original{RrrOptions()};
  {
    SessionStore<Pose2> store(path_, "map", /*checkpoint_keyframes=*/100);
    Record(&original, &store, 650, 7);
  }
  MapVerifier<Pose2> resumed{RrrOptions()};
  SessionStore<Pose2> store(path_, "map", 100);
  const ResumeSummary summary = store.Resume(&resumed, nullptr);
  // A checkpoint came with each commit that brought 100 keyframes or more
  // since the last: the last with update 90 (after 630 poses); the three
  // updates after it ran again.
  EXPECT_EQ(summary.checkpoint_update, 90);
  EXPECT_FALSE(summary.checkpoint_of_other_options);
  EXPECT_EQ(summary.updates, (650 + 6) / 7);
  EXPECT_EQ(summary.keyframes, 650);
  EXPECT_EQ(summary.differing_decisions, 0);
  EXPECT_EQ(States(resumed), States(original));
  // Both go on alike to the end of the world.
  Record(&resumed, &store, world_.graph.num_poses(), 7, true, 650);
  SessionStore<Pose2> scratch(dir_.File("scratch.db"), "map", 0);
  Record(&original, &scratch, world_.graph.num_poses(), 7, true, 650);
  EXPECT_EQ(States(resumed), States(original));
  EXPECT_GT(original.AcceptedLoops().size(), 0u);
}

TEST_F(SessionStoreTest, ACrashedSessionResumesFromItsCheckpoint) {
  {
    MapVerifier<Pose2> verifier{RrrOptions()};
    SessionStore<Pose2> store(path_, "map", 50);
    Record(&verifier, &store, 400, 10, /*commit_last=*/false);
  }
  MapVerifier<Pose2> resumed{RrrOptions()};
  SessionStore<Pose2> store(path_, "map", 50);
  const ResumeSummary summary = store.Resume(&resumed, nullptr);
  EXPECT_EQ(summary.checkpoint_update, 35);  // after pose 349
  EXPECT_EQ(summary.keyframes, 390);
  MapVerifier<Pose2> reference{RrrOptions()};
  {
    SessionStore<Pose2> fresh(dir_.File("reference.db"), "map", 0);
    Record(&reference, &fresh, summary.keyframes, 10);
  }
  EXPECT_EQ(States(resumed), States(reference));
}

TEST_F(SessionStoreTest, RunsEveryUpdateAgainWhenTheOptionsChanged) {
  {
    MapVerifier<Pose2> verifier{RrrOptions()};
    SessionStore<Pose2> store(path_, "map", 100);
    Record(&verifier, &store, 500, 10);
  }
  RrrOptions other;
  other.noise_margin = 4.0;
  MapVerifier<Pose2> resumed(other);
  SessionStore<Pose2> store(path_, "map", 100);
  const ResumeSummary summary = store.Resume(&resumed, nullptr);
  EXPECT_TRUE(summary.checkpoint_of_other_options);
  EXPECT_EQ(summary.checkpoint_update, 0);
  EXPECT_EQ(summary.updates, 50);
  MapVerifier<Pose2> reference(other);
  {
    SessionStore<Pose2> fresh(dir_.File("reference.db"), "map", 0);
    Record(&reference, &fresh, 500, 10);
  }
  EXPECT_EQ(States(resumed), States(reference));
}

TEST_F(SessionStoreTest, RefusesACheckpointThatIsNotOne) {
  {
    MapVerifier<Pose2> verifier{RrrOptions()};
    SessionStore<Pose2> store(path_, "map", 100);
    Record(&verifier, &store, 300, 10);
  }
  for (const char* state : {"x'00'", "substr(state, 1, 4000)"}) {
    Tamper(path_, std::string("UPDATE checkpoint SET state = ") + state);
    MapVerifier<Pose2> resumed{RrrOptions()};
    SessionStore<Pose2> store(path_, "map");
    const std::string error = ErrorOf([&] { store.Resume(&resumed, nullptr); });
    EXPECT_EQ(error.rfind(path_, 0), 0u) << error;
    EXPECT_NE(error.find("the checkpoint after update 30: "), std::string::npos)
        << error;
  }
}

TEST_F(SessionStoreTest, BringsAVersionTwoDatabaseUpToDate) {
  RecordFirstPoses(200);
  Tamper(path_,
         "DROP TABLE checkpoint; UPDATE meta SET value = '2' WHERE key = "
         "'schema_version'");
  EXPECT_EQ(std::get<PoseGraph2>(ReadSession(path_).graph).num_poses(), 200);
  MapVerifier<Pose2> resumed{RrrOptions()};
  {
    SessionStore<Pose2> store(path_, "map", 1);
    EXPECT_EQ(store.Resume(&resumed, nullptr).checkpoint_update, 0);
    store.CommitUpdate(false, resumed.Update(), &resumed);
  }
  MapVerifier<Pose2> again{RrrOptions()};
  SessionStore<Pose2> store(path_, "map");
  EXPECT_EQ(store.Resume(&again, nullptr).checkpoint_update, 21);
  EXPECT_EQ(States(again), States(resumed));
}

TEST_F(SessionStoreTest, RefusesAWaitingCandidateThatIsNotOne) {
  {
    SessionStore<Pose2> store(path_, "map");
    store.RecordStampedWaiting(0, 1, 2, Pose2(), Pose2::Jacobian::Identity());
    store.CommitUpdate(false, {});
  }
  Tamper(path_, "UPDATE waiting_by_stamp SET information = x'00'");
  MapVerifier<Pose2> resumed{RrrOptions()};
  SessionStore<Pose2> store(path_, "map");
  const std::string error = ErrorOf([&] { store.Resume(&resumed, nullptr); });
  EXPECT_EQ(error.rfind(path_, 0), 0u) << error;
  EXPECT_NE(error.find("holds 1 bytes"), std::string::npos) << error;
}

}  // namespace
}  // namespace rrr
