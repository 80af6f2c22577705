// A thin owner of an SQLite connection and its prepared statements, with
// every failure turned into a SessionError naming the file.
#ifndef RRR_CORE_SESSION_SQLITE_DB_H_
#define RRR_CORE_SESSION_SQLITE_DB_H_

#include <sqlite3.h>

#include <cstdint>
#include <string>
#include <vector>

namespace rrr {

class SqliteDb;

// A prepared statement. Bind parameters (1-based), Step() through the rows,
// Reset() to run it again.
class SqliteStatement {
 public:
  SqliteStatement(SqliteDb* db, const std::string& sql);
  ~SqliteStatement();
  SqliteStatement(const SqliteStatement&) = delete;
  SqliteStatement& operator=(const SqliteStatement&) = delete;

  void Bind(int index, std::int64_t value);
  void Bind(int index, const std::string& text);
  void BindNull(int index);
  void Bind(int index, const std::vector<double>& values);  // as a blob
  void BindBlob(int index, const std::string& bytes);
  // Runs to the next row; false when there are no more.
  bool Step();
  void Reset();

  bool IsNull(int column) const;
  std::int64_t Int(int column) const;
  std::string Text(int column) const;
  // A blob of `count` doubles; throws SessionError if it is another size.
  std::vector<double> Doubles(int column, size_t count) const;
  // The blob of `column`, byte for byte.
  std::string Blob(int column) const;
  // The size of the blob of `column` in bytes.
  size_t NumBytes(int column) const;

 private:
  SqliteDb* db_;
  sqlite3_stmt* statement_ = nullptr;
};

// An open database. Throws SessionError("PATH: PROBLEM") on every failure.
class SqliteDb {
 public:
  // `create`: create the file if it is missing (else it must exist).
  SqliteDb(const std::string& path, bool create);
  ~SqliteDb();
  SqliteDb(const SqliteDb&) = delete;
  SqliteDb& operator=(const SqliteDb&) = delete;

  void Execute(const std::string& sql);
  // Throws SessionError with `what` and SQLite's message unless `code` is
  // one of the success codes.
  void Check(int code, const std::string& what);
  [[noreturn]] void Fail(const std::string& problem) const;
  sqlite3* handle() { return db_; }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  sqlite3* db_ = nullptr;
};

}  // namespace rrr

#endif  // RRR_CORE_SESSION_SQLITE_DB_H_
