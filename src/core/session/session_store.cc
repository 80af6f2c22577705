#include "rrr/session/session_store.h"

#include <algorithm>
#include <fstream>
#include <limits>
#include <map>
#include <string>
#include <utility>

#include "compressed_blob.h"
#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/session/session.h"
#include "session_codec.h"
#include "session_schema.h"
#include "sqlite_db.h"

namespace rrr {
namespace {

// The numbers the next input and the next update of `db` take.
void NextNumbers(SqliteDb* db, std::int64_t* seq, std::int64_t* update) {
  SqliteStatement last(db,
                       "SELECT coalesce(max(seq), 0), (SELECT "
                       "coalesce(max(number), 0) FROM updates) FROM inputs");
  last.Step();
  *seq = last.Int(0) + 1;
  *update = last.Int(1) + 1;
}

// Writes update `number`, which came after the inputs up to `last_seq`,
// and the decisions it changed, inside the caller's transaction.
void AppendUpdate(SqliteDb* db, std::int64_t number, std::int64_t last_seq,
                  bool finish, const std::vector<DecisionChange>& changes) {
  SqliteStatement update(
      db, "INSERT INTO updates(number, last_seq, finish) VALUES (?, ?, ?)");
  update.Bind(1, number);
  update.Bind(2, last_seq);
  update.Bind(3, static_cast<std::int64_t>(finish));
  update.Step();
  SqliteStatement decision(db,
                           "INSERT INTO decisions(update_number, candidate, "
                           "state) VALUES (?, ?, ?)");
  for (const DecisionChange& change : changes) {
    decision.Bind(1, number);
    decision.Bind(2, static_cast<std::int64_t>(change.candidate));
    decision.Bind(3, static_cast<std::int64_t>(change.current));
    decision.Step();
    decision.Reset();
  }
}

struct UpdateRow {
  std::int64_t number, last_seq;
  bool finish;
};

// The updates recorded, in order.
std::vector<UpdateRow> ReadUpdates(SqliteDb* db) {
  SqliteStatement query(
      db, "SELECT number, last_seq, finish FROM updates ORDER BY number");
  std::vector<UpdateRow> updates;
  while (query.Step()) {
    updates.push_back({query.Int(0), query.Int(1), query.Int(2) != 0});
  }
  return updates;
}

// The last recorded state of each candidate that has a decision.
std::map<int, LoopState> ReadFinalStates(SqliteDb* db) {
  SqliteStatement query(db,
                        "SELECT candidate, state FROM decisions "
                        "ORDER BY update_number, rowid");
  std::map<int, LoopState> states;
  while (query.Step()) {
    const std::int64_t state = query.Int(1);
    if (state < 0 || state > 2) {
      db->Fail("a decision has the unknown state " + std::to_string(state));
    }
    states[static_cast<int>(query.Int(0))] = static_cast<LoopState>(state);
  }
  return states;
}

// The checkpoint, if the database has one.
struct CheckpointRow {
  std::int64_t update_number = 0;
  std::int64_t last_seq = 0;
  std::string state;
};
bool ReadCheckpoint(SqliteDb* db, CheckpointRow* checkpoint) {
  SqliteStatement query(db,
                        "SELECT update_number, last_seq, state FROM checkpoint "
                        "ORDER BY update_number DESC LIMIT 1");
  if (!query.Step()) return false;
  checkpoint->update_number = query.Int(0);
  checkpoint->last_seq = query.Int(1);
  checkpoint->state = query.Blob(2);
  return true;
}

}  // namespace

template <class Pose>
class SessionStore<Pose>::Impl {
 public:
  Impl(const std::string& path, const std::vector<std::string>& robots,
       const RrrOptions& options, int checkpoint_keyframes)
      : db(path, true), checkpoint_keyframes(checkpoint_keyframes) {
    const int dimension = DimensionOf(static_cast<const Pose*>(nullptr));
    const std::string procedure = ToString(options.procedure);
    PrepareForRecording(
        &db, {{"schema_version", std::to_string(kSessionSchemaVersion)},
              {"dimension", std::to_string(dimension)},
              {"procedure", procedure},
              {"options", OptionsText(options)}});
    CheckRecordedAs(&db, dimension, procedure);
    // The recorded robots, and the new ones after them.
    SqliteStatement names(&db, "SELECT robot, name FROM robots ORDER BY robot");
    while (names.Step()) recorded_robots.push_back(names.Text(1));
    SqliteStatement add(&db, "INSERT INTO robots(robot, name) VALUES (?, ?)");
    for (const std::string& name : robots) {
      auto it = std::find(recorded_robots.begin(), recorded_robots.end(), name);
      if (it == recorded_robots.end()) {
        add.Bind(1, static_cast<std::int64_t>(recorded_robots.size()));
        add.Bind(2, name);
        add.Step();
        add.Reset();
        recorded_robots.push_back(name);
        it = recorded_robots.end() - 1;
      }
      stored_robot.push_back(it - recorded_robots.begin());
    }
    NextNumbers(&db, &next_seq, &next_update);
    insert_input = std::make_unique<SqliteStatement>(
        &db,
        "INSERT INTO inputs(seq, kind, robot, stamp_ns, odometry_pose, "
        "covariance, to_robot, from_id, to_id, measurement, information, "
        "number) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)");
  }

  SqliteDb db;
  int checkpoint_keyframes;
  // Keyframes committed (or resumed) since the last checkpoint.
  std::int64_t keyframes_since_checkpoint = 0;
  std::vector<std::string> recorded_robots;  // by stored index
  std::vector<std::int64_t> stored_robot;    // by the session's robot index
  std::unique_ptr<SqliteStatement> insert_input;
  std::int64_t next_seq = 1, next_update = 1;
  // Rows recorded since the last commit.
  struct Pending {
    InputKind kind;
    std::int64_t number = 0;
    std::int64_t robot = 0;
    KeyframeRecord<Pose> keyframe;
    std::int64_t to_robot = 0, from_id = 0, to_id = 0;
    std::vector<double> measurement, information;
  };
  std::vector<Pending> pending;
};

template <class Pose>
SessionStore<Pose>::SessionStore(const std::string& path,
                                 const std::vector<std::string>& robots,
                                 const RrrOptions& options,
                                 int checkpoint_keyframes)
    : impl_(std::make_unique<Impl>(path, robots, options,
                                   checkpoint_keyframes)) {}

template <class Pose>
SessionStore<Pose>::~SessionStore() = default;

template <class Pose>
const std::string& SessionStore<Pose>::path() const {
  return impl_->db.path();
}

template <class Pose>
int SessionStore<Pose>::num_uncommitted() const {
  return static_cast<int>(impl_->pending.size());
}

template <class Pose>
void SessionStore<Pose>::Keyframe(int robot,
                                  const KeyframeRecord<Pose>& keyframe,
                                  bool new_session, std::int64_t id,
                                  const Information& information) {
  typename Impl::Pending row;
  row.kind = new_session ? kSessionStart : kNextKeyframe;
  row.number = id;
  row.robot = impl_->stored_robot.at(robot);
  row.keyframe = keyframe;
  if (!new_session) row.information = Encode(information);
  impl_->pending.push_back(std::move(row));
}

template <class Pose>
void SessionStore<Pose>::RecordCandidate(std::int64_t message, int robot_a,
                                         std::int64_t a, int robot_b,
                                         std::int64_t b, const Pose& z,
                                         const Information& information,
                                         bool by_stamp) {
  typename Impl::Pending row;
  row.kind = by_stamp ? kCandidateByStamp : kCandidate;
  row.number = message;
  row.robot = impl_->stored_robot.at(robot_a);
  row.to_robot = impl_->stored_robot.at(robot_b);
  row.from_id = a;
  row.to_id = b;
  row.measurement = Encode(z);
  row.information = Encode(information);
  impl_->pending.push_back(std::move(row));
}

template <class Pose>
void SessionStore<Pose>::CommitUpdate(
    bool finish, const std::vector<DecisionChange>& changes,
    const OnlineVerifier<Pose>* verifier) {
  Impl& s = *impl_;
  std::int64_t keyframes = s.keyframes_since_checkpoint;
  for (const auto& row : s.pending) {
    keyframes += row.kind == kSessionStart || row.kind == kNextKeyframe;
  }
  std::int64_t seq = s.next_seq;
  s.db.Execute("BEGIN IMMEDIATE");
  try {
    SqliteStatement& insert = *s.insert_input;
    for (const typename Impl::Pending& row : s.pending) {
      for (int column = 1; column <= 11; ++column) insert.BindNull(column);
      insert.Bind(12, row.number);
      insert.Bind(1, seq++);
      insert.Bind(2, static_cast<std::int64_t>(row.kind));
      insert.Bind(3, row.robot);
      if (row.kind == kCandidate || row.kind == kCandidateByStamp) {
        insert.Bind(7, row.to_robot);
        insert.Bind(8, row.from_id);
        insert.Bind(9, row.to_id);
        insert.Bind(10, row.measurement);
        insert.Bind(11, row.information);
      } else {
        insert.Bind(4, row.keyframe.stamp_ns);
        insert.Bind(5, Encode(row.keyframe.odometry_pose));
        insert.Bind(6, Encode(row.keyframe.covariance));
        if (row.kind == kNextKeyframe) insert.Bind(11, row.information);
      }
      insert.Step();
      insert.Reset();
    }
    AppendUpdate(&s.db, s.next_update, seq - 1, finish, changes);
    if (verifier && s.checkpoint_keyframes > 0 &&
        keyframes >= s.checkpoint_keyframes) {
      const std::string state = verifier->SaveState();
      if (!state.empty()) {
        s.db.Execute("DELETE FROM checkpoint");
        SqliteStatement checkpoint(
            &s.db,
            "INSERT INTO checkpoint(update_number, last_seq, state) VALUES "
            "(?, ?, ?)");
        checkpoint.Bind(1, s.next_update);
        checkpoint.Bind(2, seq - 1);
        checkpoint.BindBlob(3, Compress(state));
        checkpoint.Step();
        keyframes = 0;
      }
    }
    s.db.Execute("COMMIT");
  } catch (...) {
    s.insert_input->Reset();
    sqlite3_exec(s.db.handle(), "ROLLBACK", nullptr, nullptr, nullptr);
    throw;
  }
  s.keyframes_since_checkpoint = keyframes;
  s.next_seq = seq;
  ++s.next_update;
  s.pending.clear();
}

template <class Pose>
ResumeSummary SessionStore<Pose>::Resume(Session<Pose>* session,
                                         OnlineVerifier<Pose>* verifier) {
  Impl& s = *impl_;
  std::vector<int> robot_of_stored;
  for (const std::string& name : s.recorded_robots) {
    robot_of_stored.push_back(session->RobotIndex(name));
  }
  const auto robot = [&](std::int64_t stored, const std::string& at) {
    if (stored < 0 ||
        stored >= static_cast<std::int64_t>(robot_of_stored.size())) {
      s.db.Fail(at + "robot " + std::to_string(stored) + " is not recorded");
    }
    const int r = robot_of_stored[stored];
    if (r < 0) {
      s.db.Fail(at + "robot '" + s.recorded_robots[stored] +
                "' is recorded but not among the robots");
    }
    return r;
  };
  ResumeSummary summary;
  CheckpointRow checkpoint;
  bool restore = false;
  // Runs `use` on the checkpoint; what it throws fails the resume, naming it.
  const auto with_checkpoint = [&](const auto& use) {
    try {
      use();
    } catch (const std::runtime_error& e) {
      s.db.Fail("the checkpoint after update " +
                std::to_string(checkpoint.update_number) + ": " + e.what());
    }
  };
  if (ReadCheckpoint(&s.db, &checkpoint)) {
    with_checkpoint([&] {
      checkpoint.state = Decompress(checkpoint.state);
      restore = verifier->SavedUnderSameOptions(checkpoint.state);
    });
    summary.checkpoint_of_other_options = !restore;
  }
  // Restores the checkpoint, once the inputs up to its last_seq are in.
  const auto restore_checkpoint = [&] {
    with_checkpoint([&] { verifier->RestoreState(checkpoint.state); });
    summary.checkpoint_update = checkpoint.update_number;
    restore = false;
    s.keyframes_since_checkpoint = 0;
  };
  const std::vector<UpdateRow> updates = ReadUpdates(&s.db);
  size_t next = 0;
  const auto run_updates_through = [&](std::int64_t seq) {
    for (; next < updates.size() && updates[next].last_seq <= seq; ++next) {
      ++summary.updates;
      if (restore && updates[next].number <= checkpoint.update_number) {
        continue;  // its work is in the checkpoint
      }
      if (restore) restore_checkpoint();
      if (updates[next].finish) {
        verifier->Finish();
      } else {
        verifier->Update();
      }
    }
    if (restore && seq == checkpoint.last_seq) restore_checkpoint();
  };
  run_updates_through(0);
  const size_t pose_size = EncodedSize(static_cast<const Pose*>(nullptr));
  SqliteStatement query(
      &s.db,
      "SELECT seq, kind, robot, stamp_ns, odometry_pose, covariance, "
      "to_robot, from_id, to_id, measurement, information, number FROM inputs "
      "ORDER BY seq");
  while (query.Step()) {
    const std::int64_t seq = query.Int(0);
    const std::string at = "input " + std::to_string(seq) + ": ";
    const auto fail = [&](const std::string& problem) {
      s.db.Fail(at + problem);
    };
    const std::int64_t kind = query.Int(1);
    const int from = robot(query.Int(2), at);
    try {
      if (kind == kCandidate || kind == kCandidateByStamp) {
        Pose z;
        Information information;
        DecodeMeasurement(s.db, query, 9, 10, at, &z, &information);
        const int to = robot(query.Int(6), at);
        if (kind == kCandidate) {
          session->AddCandidate(query.Int(11), from, query.Int(7), to,
                                query.Int(8), z, information);
        } else {
          session->AddCandidateByStamp(query.Int(11), from, query.Int(7), to,
                                       query.Int(8), z, information);
        }
        ++summary.candidates;
      } else if (kind == kSessionStart || kind == kNextKeyframe) {
        KeyframeRecord<Pose> keyframe;
        keyframe.stamp_ns = query.Int(3);
        keyframe.odometry_pose =
            DecodePose(FiniteDoubles(s.db, query, 4, pose_size, "a pose", at),
                       static_cast<const Pose*>(nullptr), fail);
        keyframe.covariance =
            FiniteMatrix<6>(s.db, query, 5, "a covariance", at);
        Information information;
        if (kind == kNextKeyframe) {
          information = DecodeInformation<Pose>(s.db, query, 10, at);
        }
        const auto taken = session->AddKeyframe(
            from, keyframe, kind == kSessionStart,
            kind == kNextKeyframe ? &information : nullptr);
        if (taken.id != query.Int(11)) {
          fail("the keyframe of robot '" + s.recorded_robots[query.Int(2)] +
               "' recorded as " + std::to_string(query.Int(11)) +
               " arrives as " + std::to_string(taken.id));
        }
        ++summary.keyframes;
        ++s.keyframes_since_checkpoint;
        if (kind == kSessionStart) ++summary.sessions;
      } else {
        fail("unknown kind " + std::to_string(kind));
      }
    } catch (const std::logic_error& e) {  // the session refused it
      fail(e.what());
    }
    run_updates_through(seq);
  }
  run_updates_through(std::numeric_limits<std::int64_t>::max());
  if (restore) {
    s.db.Fail("the checkpoint after update " +
              std::to_string(checkpoint.update_number) + " follows input " +
              std::to_string(checkpoint.last_seq) + ", which is not recorded");
  }
  for (const auto& [candidate, state] : ReadFinalStates(&s.db)) {
    if (candidate >= verifier->num_candidates() ||
        verifier->state(candidate) != state) {
      ++summary.differing_decisions;
    }
  }
  return summary;
}

template class SessionStore<Pose2>;
template class SessionStore<Pose3>;

}  // namespace rrr
