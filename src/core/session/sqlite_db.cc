#include "sqlite_db.h"

#include <cstring>

#include "rrr/session/session_store.h"

namespace rrr {

SqliteDb::SqliteDb(const std::string& path, bool create) : path_(path) {
  // Without `create`, the file is opened for reading and writing all the
  // same: a WAL database left by a crash can only be read that way.
  const int flags = SQLITE_OPEN_READWRITE | (create ? SQLITE_OPEN_CREATE : 0);
  const int code = sqlite3_open_v2(path.c_str(), &db_, flags, nullptr);
  if (code != SQLITE_OK) {
    const std::string message =
        db_ ? sqlite3_errmsg(db_) : sqlite3_errstr(code);
    sqlite3_close(db_);
    db_ = nullptr;
    Fail("cannot open the database: " + message);
  }
  sqlite3_extended_result_codes(db_, 1);
  sqlite3_busy_timeout(db_, 5000);
}

SqliteDb::~SqliteDb() { sqlite3_close(db_); }

void SqliteDb::Execute(const std::string& sql) {
  char* error = nullptr;
  const int code = sqlite3_exec(db_, sql.c_str(), nullptr, nullptr, &error);
  if (code != SQLITE_OK) {
    const std::string message = error ? error : sqlite3_errstr(code);
    sqlite3_free(error);
    Fail(message);
  }
}

void SqliteDb::Check(int code, const std::string& what) {
  if (code == SQLITE_OK || code == SQLITE_ROW || code == SQLITE_DONE) return;
  Fail(what + ": " + sqlite3_errmsg(db_));
}

void SqliteDb::Fail(const std::string& problem) const {
  throw SessionError(path_, problem);
}

SqliteStatement::SqliteStatement(SqliteDb* db, const std::string& sql)
    : db_(db) {
  db_->Check(
      sqlite3_prepare_v2(db_->handle(), sql.c_str(), -1, &statement_, nullptr),
      "cannot read it as a session database");
}

SqliteStatement::~SqliteStatement() { sqlite3_finalize(statement_); }

void SqliteStatement::Bind(int index, std::int64_t value) {
  db_->Check(sqlite3_bind_int64(statement_, index, value), "bind");
}

void SqliteStatement::Bind(int index, const std::string& text) {
  db_->Check(sqlite3_bind_text(statement_, index, text.c_str(),
                               static_cast<int>(text.size()), SQLITE_TRANSIENT),
             "bind");
}

void SqliteStatement::BindNull(int index) {
  db_->Check(sqlite3_bind_null(statement_, index), "bind");
}

void SqliteStatement::Bind(int index, const std::vector<double>& values) {
  db_->Check(sqlite3_bind_blob(statement_, index, values.data(),
                               static_cast<int>(values.size() * sizeof(double)),
                               SQLITE_TRANSIENT),
             "bind");
}

void SqliteStatement::BindBlob(int index, const std::string& bytes) {
  db_->Check(sqlite3_bind_blob64(statement_, index, bytes.data(), bytes.size(),
                                 SQLITE_TRANSIENT),
             "bind");
}

bool SqliteStatement::Step() {
  const int code = sqlite3_step(statement_);
  db_->Check(code, "cannot read or write the session");
  return code == SQLITE_ROW;
}

void SqliteStatement::Reset() {
  sqlite3_reset(statement_);
  sqlite3_clear_bindings(statement_);
}

bool SqliteStatement::IsNull(int column) const {
  return sqlite3_column_type(statement_, column) == SQLITE_NULL;
}

std::int64_t SqliteStatement::Int(int column) const {
  if (sqlite3_column_type(statement_, column) != SQLITE_INTEGER) {
    db_->Fail(std::string("column ") + sqlite3_column_name(statement_, column) +
              " holds no integer");
  }
  return sqlite3_column_int64(statement_, column);
}

std::string SqliteStatement::Text(int column) const {
  const unsigned char* text = sqlite3_column_text(statement_, column);
  return text ? reinterpret_cast<const char*>(text) : "";
}

std::vector<double> SqliteStatement::Doubles(int column, size_t count) const {
  const void* blob = sqlite3_column_blob(statement_, column);
  const int bytes = sqlite3_column_bytes(statement_, column);
  if (bytes != static_cast<int>(count * sizeof(double))) {
    db_->Fail(std::string("column ") + sqlite3_column_name(statement_, column) +
              " holds " + std::to_string(bytes) + " bytes, not " +
              std::to_string(count) + " numbers");
  }
  std::vector<double> values(count);
  if (count > 0) std::memcpy(values.data(), blob, bytes);
  return values;
}

std::string SqliteStatement::Blob(int column) const {
  const void* blob = sqlite3_column_blob(statement_, column);
  const int bytes = sqlite3_column_bytes(statement_, column);
  return blob ? std::string(static_cast<const char*>(blob), bytes) : "";
}

size_t SqliteStatement::NumBytes(int column) const {
  return static_cast<size_t>(sqlite3_column_bytes(statement_, column));
}

}  // namespace rrr
