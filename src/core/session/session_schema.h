// The schema of a session database and its checks (internal to the session
// library): what SessionStore writes and reads.
#ifndef RRR_CORE_SESSION_SESSION_SCHEMA_H_
#define RRR_CORE_SESSION_SESSION_SCHEMA_H_

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "sqlite_db.h"

namespace rrr {

// What a row of the inputs table is.
enum InputKind : std::int64_t {
  kSessionStart = 0,      // a keyframe that started a session
  kNextKeyframe = 1,      // a keyframe of the robot's current session
  kCandidate = 2,         // by keyframe ids
  kCandidateByStamp = 3,  // by stamps (ns), in the columns of the ids
};

// The tables of a session database (schema version kSessionSchemaVersion).
inline constexpr const char* kSchema = R"sql(
CREATE TABLE meta(key TEXT PRIMARY KEY, value TEXT NOT NULL);
CREATE TABLE robots(robot INTEGER PRIMARY KEY, name TEXT NOT NULL UNIQUE);
CREATE TABLE inputs(
  seq INTEGER PRIMARY KEY,       -- arrival order
  kind INTEGER NOT NULL,  -- 0 session start, 1 keyframe, 2 candidate, 3 by stamp
  robot INTEGER NOT NULL,        -- keyframes; candidates: the from end's
  number INTEGER NOT NULL,       -- keyframe id, or the candidate's message
  stamp_ns INTEGER,              -- keyframes
  odometry_pose BLOB,            -- keyframes: pose in the robot's odometry
  covariance BLOB,               -- keyframes: its 6 x 6 covariance (*)
  to_robot INTEGER,              -- candidates
  from_id INTEGER, to_id INTEGER,  -- candidates: keyframe ids (or stamps)
  measurement BLOB, information BLOB);  -- candidates (*)
-- (*) the upper triangle, row by row, if symmetric, else every entry.
CREATE TABLE updates(number INTEGER PRIMARY KEY,
  last_seq INTEGER NOT NULL,   -- the inputs up to here came before it
  finish INTEGER NOT NULL);
CREATE TABLE decisions(update_number INTEGER NOT NULL,
  candidate INTEGER NOT NULL, state INTEGER NOT NULL);
-- At most one row: the procedure's state (OnlineVerifier::SaveState, stored
-- compressed by Compress) after update `update_number`, which came after
-- the inputs up to `last_seq`.
CREATE TABLE checkpoint(update_number INTEGER PRIMARY KEY,
  last_seq INTEGER NOT NULL, state BLOB NOT NULL);
)sql";

// The value of `key` in the meta table; fails if there is none.
std::string MetaValue(SqliteDb* db, const std::string& key);

// Checks that `db` is a session database of the schema version this
// library reads, with its tables (an earlier version is refused, naming
// it); returns its dimension (2 or 3).
int CheckSchema(SqliteDb* db);

// Sets the WAL journal of a database opened to record and, if it has no
// table yet, creates kSchema and the `meta` rows (key, value) in it.
void PrepareForRecording(
    SqliteDb* db, const std::vector<std::pair<std::string, std::string>>& meta);

// Fails unless `db`, recorded by the procedure its meta names, is resumed
// in `dimension` by `procedure`.
void CheckRecordedAs(SqliteDb* db, int dimension, const std::string& procedure);

}  // namespace rrr

#endif  // RRR_CORE_SESSION_SESSION_SCHEMA_H_
