// The session database's table of loop candidates that wait for keyframes
// by stamp.
#ifndef RRR_CORE_SESSION_STAMPED_WAITING_TABLE_H_
#define RRR_CORE_SESSION_STAMPED_WAITING_TABLE_H_

#include <cstdint>
#include <memory>
#include <vector>

#include "rrr/session/session_store.h"
#include "sqlite_db.h"

namespace rrr {

// Candidates named by stamp are held outside the verifier until keyframes
// near both stamps exist. The table holds those held as of the last commit:
// Hold and Release are kept in memory and written by Write inside the
// caller's transaction.
template <class Pose>
class StampedWaitingTable {
 public:
  using Information = typename Constraint<Pose>::Information;

  static constexpr const char* kSchema =
      "CREATE TABLE IF NOT EXISTS waiting_by_stamp("
      "key INTEGER PRIMARY KEY, message INTEGER NOT NULL, "
      "from_stamp_ns INTEGER NOT NULL, "
      "to_stamp_ns INTEGER NOT NULL, measurement BLOB NOT NULL, "
      "information BLOB NOT NULL);";

  // `db` holds the table (kSchema) and outlives this.
  explicit StampedWaitingTable(SqliteDb* db);

  // Returns the new candidate's key, greater than any the table held.
  std::int64_t Hold(std::int64_t message, std::int64_t from_ns,
                    std::int64_t to_ns, const Pose& z,
                    const Information& information);
  void Release(std::int64_t key);
  int num_pending() const { return static_cast<int>(pending_.size()); }
  // Writes the pending changes (in the caller's transaction).
  void Write();
  // After the transaction: forget the pending changes once committed, or
  // keep them for the next try if it failed.
  void Committed() { pending_.clear(); }
  void Failed();

  // The candidates held as of the last commit, by key.
  std::vector<StampedWaiting<Pose>> Read() const;

 private:
  struct Change {
    std::int64_t key = 0;
    bool hold = true;  // else a release
    std::int64_t message = 0, from_ns = 0, to_ns = 0;
    std::vector<double> measurement, information;
  };
  SqliteDb* db_;
  std::unique_ptr<SqliteStatement> insert_, erase_;
  std::int64_t next_key_ = 1;
  std::vector<Change> pending_;
};

}  // namespace rrr

#endif  // RRR_CORE_SESSION_STAMPED_WAITING_TABLE_H_
