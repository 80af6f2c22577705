// The tables of a session database: their schema, and their rows read back
// checked (internal to the session library).
#ifndef RRR_CORE_SESSION_SESSION_TABLES_H_
#define RRR_CORE_SESSION_SESSION_TABLES_H_

#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "rrr/session/session_store.h"
#include "session_codec.h"
#include "sqlite_db.h"

namespace rrr {

// What a row of the inputs table is.
enum InputKind : std::int64_t { kFirstKeyframe = 0, kKeyframe = 1, kLoop = 2 };

inline constexpr const char* kSchema = R"sql(
CREATE TABLE meta(key TEXT PRIMARY KEY, value TEXT NOT NULL);
CREATE TABLE inputs(
  seq INTEGER PRIMARY KEY,     -- arrival order
  kind INTEGER NOT NULL,       -- 0 first keyframe, 1 keyframe, 2 candidate
  pose_id INTEGER,             -- keyframes
  stamp_ns INTEGER,            -- keyframes
  odometry_pose BLOB,          -- keyframes: pose in the odometry frame
  covariance BLOB,             -- keyframes: its 6 x 6 covariance (*)
  candidate INTEGER,           -- candidates: number in arrival order
  from_id INTEGER, to_id INTEGER,  -- candidates
  measurement BLOB,            -- odometry edge or candidate
  information BLOB);           -- odometry edge or candidate (*)
-- (*) the upper triangle, row by row, if symmetric, else every entry.
)sql";

// The updates and the decisions each changed, in a robot's database and in a
// fleet's.
inline constexpr const char* kUpdatesSchema = R"sql(
CREATE TABLE updates(number INTEGER PRIMARY KEY,
  last_seq INTEGER NOT NULL,   -- the inputs up to here came before it
  finish INTEGER NOT NULL);
CREATE TABLE decisions(update_number INTEGER NOT NULL,
  candidate INTEGER NOT NULL, state INTEGER NOT NULL);
)sql";

// Sets the WAL journal of a database opened to record and, if it has no
// table yet, creates `schema` and the `meta` rows (key, value) in it.
void PrepareForRecording(
    SqliteDb* db, const std::string& schema,
    const std::vector<std::pair<std::string, std::string>>& meta);

// Fails unless a database of `what` ("session", "fleet") recorded in
// `recorded_dimension` by the procedure its meta names is resumed in
// `dimension` by `procedure`.
void CheckRecordedAs(SqliteDb* db, const std::string& what,
                     int recorded_dimension, int dimension,
                     const std::string& procedure);

// The numbers the next input and the next update of `db` take.
void NextNumbers(SqliteDb* db, std::int64_t* seq, std::int64_t* update);

// Writes updates and the decisions they changed, inside the caller's
// transaction.
class UpdateLog {
 public:
  explicit UpdateLog(SqliteDb* db);
  // Writes update `number`, which came after the inputs up to `last_seq`.
  void Append(std::int64_t number, std::int64_t last_seq, bool finish,
              const std::vector<DecisionChange>& changes);
  // Readies the statements again after a failed transaction.
  void Reset();

 private:
  SqliteStatement insert_update_, insert_decision_;
};

// At most one row: the verifier's state (OnlineVerifier::SaveState, stored
// compressed by Compress) after update `update_number`, which came after the
// inputs up to `last_seq`.
inline constexpr const char* kCheckpointSchema = R"sql(
CREATE TABLE IF NOT EXISTS checkpoint(update_number INTEGER PRIMARY KEY,
  last_seq INTEGER NOT NULL, state BLOB NOT NULL);
)sql";

// The checkpoint, if the database has one.
struct CheckpointRow {
  std::int64_t update_number = 0;
  std::int64_t last_seq = 0;
  std::string state;
};
bool ReadCheckpoint(SqliteDb* db, CheckpointRow* checkpoint);

inline constexpr const char* kInsertInput =
    "INSERT INTO inputs(seq, kind, pose_id, stamp_ns, odometry_pose, "
    "covariance, candidate, from_id, to_id, measurement, information) "
    "VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)";

// One row of the inputs table, decoded and checked.
template <class Pose>
struct InputRow {
  using Information = typename Constraint<Pose>::Information;
  std::int64_t seq = 0;
  InputKind kind = kFirstKeyframe;
  PoseId pose_id = 0;
  KeyframeRecord<Pose> keyframe;
  int candidate = 0;
  PoseId from = 0, to = 0;
  Pose measurement;
  Information information = Information::Identity();
};

// Calls `visit` with each input in arrival order. Fails on a row that is
// not a well-formed input (unknown kind, missing or non-finite values, an
// information matrix that is not symmetric positive definite).
template <class Pose>
void ForEachInput(SqliteDb* db,
                  const std::function<void(const InputRow<Pose>&)>& visit) {
  const size_t pose_size = EncodedSize(static_cast<const Pose*>(nullptr));
  SqliteStatement query(
      db,
      "SELECT seq, kind, pose_id, stamp_ns, odometry_pose, covariance, "
      "candidate, from_id, to_id, measurement, information FROM inputs "
      "ORDER BY seq");
  InputRow<Pose> row;
  while (query.Step()) {
    row.seq = query.Int(0);
    const std::string at = "input " + std::to_string(row.seq) + ": ";
    const auto fail = [&](const std::string& problem) {
      db->Fail(at + problem);
    };
    const std::int64_t kind = query.Int(1);
    if (kind < kFirstKeyframe || kind > kLoop) {
      fail("unknown kind " + std::to_string(kind));
    }
    row.kind = static_cast<InputKind>(kind);
    if (row.kind == kLoop) {
      const std::int64_t number = query.Int(6);
      if (number < 0 || number > std::numeric_limits<int>::max()) {
        fail("candidate number " + std::to_string(number) + " is out of range");
      }
      row.candidate = static_cast<int>(number);
      row.from = query.Int(7);
      row.to = query.Int(8);
    } else {
      row.pose_id = query.Int(2);
      row.keyframe.stamp_ns = query.Int(3);
      row.keyframe.odometry_pose =
          DecodePose(FiniteDoubles(*db, query, 4, pose_size, "a pose", at),
                     static_cast<const Pose*>(nullptr), fail);
      row.keyframe.covariance =
          FiniteMatrix<6>(*db, query, 5, "a covariance", at);
    }
    if (row.kind != kFirstKeyframe) {
      DecodeMeasurement(*db, query, 9, 10, at, &row.measurement,
                        &row.information);
    }
    visit(row);
  }
}

struct UpdateRow {
  std::int64_t number, last_seq;
  bool finish;
};

// The updates recorded, in order.
std::vector<UpdateRow> ReadUpdates(SqliteDb* db);

// The last recorded state of each candidate that has a decision.
std::map<int, LoopState> ReadFinalStates(SqliteDb* db);

// The value of `key` in the meta table; fails if there is none.
std::string MetaValue(SqliteDb* db, const std::string& key);

// Whether `db` is a fleet's session database (FleetStore).
bool IsFleetDatabase(SqliteDb* db);

// Checks that `db` is a session database of a schema version this library
// reads (1 to kSessionSchemaVersion) with the tables of that version;
// returns its dimension (2 or 3) and sets `*version`.
int CheckSchema(SqliteDb* db, int* version);

}  // namespace rrr

#endif  // RRR_CORE_SESSION_SESSION_TABLES_H_
