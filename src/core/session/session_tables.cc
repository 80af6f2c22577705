#include "session_tables.h"

#include <utility>

namespace rrr {

void PrepareForRecording(
    SqliteDb* db, const std::string& schema,
    const std::vector<std::pair<std::string, std::string>>& meta) {
  db->Execute("PRAGMA journal_mode = WAL; PRAGMA synchronous = NORMAL;");
  SqliteStatement count(db, "SELECT count(*) FROM sqlite_master");
  count.Step();
  if (count.Int(0) != 0) return;
  db->Execute("BEGIN;" + schema + "COMMIT;");
  SqliteStatement insert(db, "INSERT INTO meta(key, value) VALUES (?, ?)");
  for (const auto& [key, value] : meta) {
    insert.Bind(1, key);
    insert.Bind(2, value);
    insert.Step();
    insert.Reset();
  }
}

void CheckRecordedAs(SqliteDb* db, const std::string& what,
                     int recorded_dimension, int dimension,
                     const std::string& procedure) {
  if (recorded_dimension != dimension) {
    db->Fail("it holds a " + std::to_string(recorded_dimension) + "D " + what +
             ", but this verifier is " + std::to_string(dimension) + "D");
  }
  const std::string recorded = MetaValue(db, "procedure");
  if (recorded != procedure) {
    db->Fail("it was recorded with the " + recorded +
             " procedure; resume it with the same procedure, not " + procedure);
  }
}

void NextNumbers(SqliteDb* db, std::int64_t* seq, std::int64_t* update) {
  SqliteStatement last(db,
                       "SELECT coalesce(max(seq), 0), (SELECT "
                       "coalesce(max(number), 0) FROM updates) FROM inputs");
  last.Step();
  *seq = last.Int(0) + 1;
  *update = last.Int(1) + 1;
}

UpdateLog::UpdateLog(SqliteDb* db)
    : insert_update_(
          db, "INSERT INTO updates(number, last_seq, finish) VALUES (?, ?, ?)"),
      insert_decision_(db,
                       "INSERT INTO decisions(update_number, candidate, state) "
                       "VALUES (?, ?, ?)") {}

void UpdateLog::Append(std::int64_t number, std::int64_t last_seq, bool finish,
                       const std::vector<DecisionChange>& changes) {
  insert_update_.Bind(1, number);
  insert_update_.Bind(2, last_seq);
  insert_update_.Bind(3, static_cast<std::int64_t>(finish));
  insert_update_.Step();
  insert_update_.Reset();
  for (const DecisionChange& change : changes) {
    insert_decision_.Bind(1, number);
    insert_decision_.Bind(2, static_cast<std::int64_t>(change.candidate));
    insert_decision_.Bind(3, static_cast<std::int64_t>(change.current));
    insert_decision_.Step();
    insert_decision_.Reset();
  }
}

void UpdateLog::Reset() {
  insert_update_.Reset();
  insert_decision_.Reset();
}

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

std::string MetaValue(SqliteDb* db, const std::string& key) {
  SqliteStatement query(db, "SELECT value FROM meta WHERE key = ?");
  query.Bind(1, key);
  if (!query.Step()) db->Fail("it has no " + key + " (not a session database)");
  return query.Text(0);
}

// Checks that `db` is a session database of a schema version this library
// reads (1 or kSessionSchemaVersion); returns its dimension (2 or 3) and
// sets `*version`.
int CheckSchema(SqliteDb* db, int* version) {
  if (IsFleetDatabase(db)) {
    db->Fail(
        "it is a fleet's session database, which rrr_node resumes with "
        "robots set");
  }
  const std::string text = MetaValue(db, "schema_version");
  *version = 0;
  for (int v = 1; v <= kSessionSchemaVersion; ++v) {
    if (text == std::to_string(v)) *version = v;
  }
  if (*version == 0) {
    db->Fail("schema version " + text + ", but this rrr reads versions 1 to " +
             std::to_string(kSessionSchemaVersion));
  }
  // Version 2 added waiting_by_stamp, version 3 the checkpoint.
  std::string tables = "'meta', 'inputs', 'updates', 'decisions'";
  int expected = 4;
  for (const auto& [since, table] : {std::make_pair(2, "'waiting_by_stamp'"),
                                     std::make_pair(3, "'checkpoint'")}) {
    if (*version < since) continue;
    tables += std::string(", ") + table;
    ++expected;
  }
  SqliteStatement count(db,
                        "SELECT count(*) FROM sqlite_master WHERE type = "
                        "'table' AND name IN (" +
                            tables + ")");
  count.Step();
  if (count.Int(0) != expected) {
    db->Fail("it is not a session database of rrr");
  }
  const std::string dimension = MetaValue(db, "dimension");
  if (dimension != "2" && dimension != "3") {
    db->Fail("dimension " + dimension + " is neither 2 nor 3");
  }
  return dimension == "2" ? 2 : 3;
}

}  // namespace rrr
