#include "session_schema.h"

#include <algorithm>
#include <fstream>
#include <string>
#include <vector>

#include "rrr/session/session_store.h"

namespace rrr {

std::string MetaValue(SqliteDb* db, const std::string& key) {
  SqliteStatement query(db, "SELECT value FROM meta WHERE key = ?");
  query.Bind(1, key);
  if (!query.Step()) db->Fail("it has no " + key + " (not a session database)");
  return query.Text(0);
}

int CheckSchema(SqliteDb* db) {
  SqliteStatement keys(db,
                       "SELECT count(*) FROM sqlite_master WHERE type = "
                       "'table' AND name = 'meta'");
  keys.Step();
  if (keys.Int(0) == 0) db->Fail("it is not a session database of rrr");
  SqliteStatement fleet(
      db, "SELECT value FROM meta WHERE key = 'fleet_schema_version'");
  if (fleet.Step()) {
    db->Fail("a fleet's database of schema version " + fleet.Text(0) +
             ", written before one robot and a fleet shared one schema; this "
             "rrr reads version " +
             std::to_string(kSessionSchemaVersion));
  }
  const std::string version = MetaValue(db, "schema_version");
  if (version != std::to_string(kSessionSchemaVersion)) {
    db->Fail("schema version " + version + ", but this rrr reads version " +
             std::to_string(kSessionSchemaVersion) +
             " (versions 1 to 3 held one robot's inputs alone)");
  }
  SqliteStatement count(db,
                        "SELECT count(*) FROM sqlite_master WHERE type = "
                        "'table' AND name IN ('meta', 'robots', 'inputs', "
                        "'updates', 'decisions', 'checkpoint')");
  count.Step();
  if (count.Int(0) != 6) db->Fail("it is not a session database of rrr");
  const std::string dimension = MetaValue(db, "dimension");
  if (dimension != "2" && dimension != "3") {
    db->Fail("dimension " + dimension + " is neither 2 nor 3");
  }
  return dimension == "2" ? 2 : 3;
}

void PrepareForRecording(
    SqliteDb* db,
    const std::vector<std::pair<std::string, std::string>>& meta) {
  db->Execute("PRAGMA journal_mode = WAL; PRAGMA synchronous = NORMAL;");
  SqliteStatement count(db, "SELECT count(*) FROM sqlite_master");
  count.Step();
  if (count.Int(0) != 0) return;
  db->Execute(std::string("BEGIN;") + kSchema + "COMMIT;");
  SqliteStatement insert(db, "INSERT INTO meta(key, value) VALUES (?, ?)");
  for (const auto& [key, value] : meta) {
    insert.Bind(1, key);
    insert.Bind(2, value);
    insert.Step();
    insert.Reset();
  }
}

void CheckRecordedAs(SqliteDb* db, int dimension,
                     const std::string& procedure) {
  const int recorded_dimension = CheckSchema(db);
  if (recorded_dimension != dimension) {
    db->Fail("it holds a " + std::to_string(recorded_dimension) +
             "D session, but this verifier is " + std::to_string(dimension) +
             "D");
  }
  const std::string recorded = MetaValue(db, "procedure");
  if (recorded != procedure) {
    db->Fail("it was recorded with the " + recorded +
             " procedure; resume it with the same procedure, not " + procedure);
  }
}

bool LooksLikeSessionDatabase(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char header[16] = {};
  in.read(header, sizeof(header));
  return in && std::string(header, 15) == "SQLite format 3";
}

std::string RobotNamesProblem(const std::vector<std::string>& robots) {
  if (robots.empty()) return "a session needs a robot";
  for (size_t r = 0; r < robots.size(); ++r) {
    if (robots.size() > 1 && robots[r].empty()) {
      return "robot " + std::to_string(r) + " of a fleet has an empty name";
    }
    if (std::count(robots.begin(), robots.end(), robots[r]) > 1) {
      return "robot '" + robots[r] + "' is named twice";
    }
  }
  return "";
}

SessionDatabase ReadSessionDatabase(const std::string& path) {
  if (!std::ifstream(path)) throw SessionError(path, "cannot be opened");
  SqliteDb db(path, false);
  SessionDatabase contents;
  contents.dimension = CheckSchema(&db);
  const std::string procedure = MetaValue(&db, "procedure");
  try {
    contents.options = ParseOptionsText(MetaValue(&db, "options"));
  } catch (const std::invalid_argument& e) {
    db.Fail(std::string("its recorded ") + e.what());
  }
  if (const std::string bad = contents.options.Validate(); !bad.empty()) {
    db.Fail("its recorded options: " + bad);
  }
  if (!ParseProcedure(procedure, &contents.options.procedure)) {
    db.Fail("the unknown procedure '" + procedure + "'");
  }
  SqliteStatement names(&db, "SELECT name FROM robots ORDER BY robot");
  while (names.Step()) contents.robots.push_back(names.Text(0));
  if (const std::string bad = RobotNamesProblem(contents.robots);
      !bad.empty()) {
    db.Fail("its robots: " + bad);
  }
  if (contents.robots.size() > 1 &&
      contents.options.procedure != Procedure::kMap) {
    db.Fail("the " + procedure + " procedure judges one robot, not " +
            std::to_string(contents.robots.size()));
  }
  return contents;
}

}  // namespace rrr
