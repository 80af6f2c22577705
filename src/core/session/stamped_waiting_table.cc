#include "stamped_waiting_table.h"

#include <string>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "session_codec.h"

namespace rrr {

template <class Pose>
StampedWaitingTable<Pose>::StampedWaitingTable(SqliteDb* db) : db_(db) {
  SqliteStatement last(db,
                       "SELECT coalesce(max(key), 0) FROM waiting_by_stamp");
  last.Step();
  next_key_ = last.Int(0) + 1;
  insert_ = std::make_unique<SqliteStatement>(
      db,
      "INSERT INTO waiting_by_stamp(key, message, from_stamp_ns, "
      "to_stamp_ns, measurement, information) VALUES (?, ?, ?, ?, ?, ?)");
  erase_ = std::make_unique<SqliteStatement>(
      db, "DELETE FROM waiting_by_stamp WHERE key = ?");
}

template <class Pose>
std::int64_t StampedWaitingTable<Pose>::Hold(std::int64_t message,
                                             std::int64_t from_ns,
                                             std::int64_t to_ns, const Pose& z,
                                             const Information& information) {
  Change change;
  change.key = next_key_++;
  change.message = message;
  change.from_ns = from_ns;
  change.to_ns = to_ns;
  change.measurement = Encode(z);
  change.information = Encode(information);
  pending_.push_back(std::move(change));
  return pending_.back().key;
}

template <class Pose>
void StampedWaitingTable<Pose>::Release(std::int64_t key) {
  Change change;
  change.key = key;
  change.hold = false;
  pending_.push_back(std::move(change));
}

template <class Pose>
void StampedWaitingTable<Pose>::Write() {
  for (const Change& change : pending_) {
    SqliteStatement& statement = change.hold ? *insert_ : *erase_;
    statement.Bind(1, change.key);
    if (change.hold) {
      statement.Bind(2, change.message);
      statement.Bind(3, change.from_ns);
      statement.Bind(4, change.to_ns);
      statement.Bind(5, change.measurement);
      statement.Bind(6, change.information);
    }
    statement.Step();
    statement.Reset();
  }
}

template <class Pose>
void StampedWaitingTable<Pose>::Failed() {
  insert_->Reset();
  erase_->Reset();
}

template <class Pose>
std::vector<StampedWaiting<Pose>> StampedWaitingTable<Pose>::Read() const {
  SqliteStatement query(db_,
                        "SELECT key, message, from_stamp_ns, to_stamp_ns, "
                        "measurement, information FROM waiting_by_stamp "
                        "ORDER BY key");
  std::vector<StampedWaiting<Pose>> held;
  while (query.Step()) {
    StampedWaiting<Pose> w;
    w.key = query.Int(0);
    w.message = query.Int(1);
    w.from_ns = query.Int(2);
    w.to_ns = query.Int(3);
    DecodeMeasurement(
        *db_, query, 4, 5,
        "candidate " + std::to_string(w.key) + " waiting by stamp: ",
        &w.measurement, &w.information);
    held.push_back(std::move(w));
  }
  return held;
}

template class StampedWaitingTable<Pose2>;
template class StampedWaitingTable<Pose3>;

}  // namespace rrr
