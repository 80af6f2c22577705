#include "session_tables.h"

#include <utility>

namespace rrr {

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
