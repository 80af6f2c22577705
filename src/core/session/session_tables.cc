#include "session_tables.h"

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
  SqliteStatement tables(
      db,
      "SELECT count(*) FROM sqlite_master WHERE type = 'table' AND "
      "name IN ('meta', 'inputs', 'updates', 'decisions', "
      "'waiting_by_stamp')");
  tables.Step();
  const std::string text = MetaValue(db, "schema_version");
  if (text == "1" || text == std::to_string(kSessionSchemaVersion)) {
    *version = std::stoi(text);
  } else {
    db->Fail("schema version " + text + ", but this rrr reads versions 1 to " +
             std::to_string(kSessionSchemaVersion));
  }
  if (tables.Int(0) != (*version == 1 ? 4 : 5)) {
    db->Fail("it is not a session database of rrr");
  }
  const std::string dimension = MetaValue(db, "dimension");
  if (dimension != "2" && dimension != "3") {
    db->Fail("dimension " + dimension + " is neither 2 nor 3");
  }
  return dimension == "2" ? 2 : 3;
}

}  // namespace rrr
