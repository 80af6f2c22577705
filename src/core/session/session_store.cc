#include "rrr/session/session_store.h"

#include <cmath>
#include <fstream>
#include <limits>
#include <map>

#include "compressed_blob.h"
#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "session_codec.h"
#include "session_tables.h"
#include "sqlite_db.h"
#include "stamped_waiting_table.h"

namespace rrr {

template <class Pose>
class SessionStore<Pose>::Impl {
 public:
  Impl(const std::string& path, const std::string& procedure,
       int checkpoint_keyframes)
      : db(path, true), checkpoint_keyframes(checkpoint_keyframes) {
    PrepareForRecording(
        &db,
        std::string(kSchema) + kUpdatesSchema +
            StampedWaitingTable<Pose>::kSchema + kCheckpointSchema,
        {{"schema_version", std::to_string(kSessionSchemaVersion)},
         {"dimension",
          std::to_string(DimensionOf(static_cast<const Pose*>(nullptr)))},
         {"procedure", procedure}});
    int version = 0;
    const int dimension = CheckSchema(&db, &version);
    if (version < kSessionSchemaVersion) {  // brought up: the tables it lacked
      db.Execute(std::string("BEGIN;") +
                 (version == 1 ? StampedWaitingTable<Pose>::kSchema : "") +
                 kCheckpointSchema + "UPDATE meta SET value = '" +
                 std::to_string(kSessionSchemaVersion) +
                 "' WHERE key = 'schema_version'; COMMIT;");
    }
    CheckRecordedAs(&db, "session", dimension,
                    DimensionOf(static_cast<const Pose*>(nullptr)), procedure);
    NextNumbers(&db, &next_seq, &next_update);
    insert_input = std::make_unique<SqliteStatement>(&db, kInsertInput);
    updates = std::make_unique<UpdateLog>(&db);
    waiting = std::make_unique<StampedWaitingTable<Pose>>(&db);
  }

  SqliteDb db;
  int checkpoint_keyframes;
  // Keyframes committed (or resumed) since the last checkpoint.
  std::int64_t keyframes_since_checkpoint = 0;
  // Prepared once, used by every CommitUpdate.
  std::unique_ptr<SqliteStatement> insert_input;
  std::unique_ptr<UpdateLog> updates;
  std::int64_t next_seq = 1, next_update = 1;
  std::unique_ptr<StampedWaitingTable<Pose>> waiting;
  // Rows recorded since the last commit, as bound values.
  struct Pending {
    InputKind kind;
    PoseId pose_id = 0;
    KeyframeRecord<Pose> keyframe;
    int candidate = 0;
    PoseId from = 0, to = 0;
    std::vector<double> measurement, information;
  };
  std::vector<Pending> pending;
};

template <class Pose>
SessionStore<Pose>::SessionStore(const std::string& path,
                                 const std::string& procedure,
                                 int checkpoint_keyframes)
    : impl_(std::make_unique<Impl>(path, procedure, checkpoint_keyframes)) {}

template <class Pose>
SessionStore<Pose>::~SessionStore() = default;

template <class Pose>
const std::string& SessionStore<Pose>::path() const {
  return impl_->db.path();
}

template <class Pose>
int SessionStore<Pose>::num_uncommitted() const {
  return static_cast<int>(impl_->pending.size()) +
         impl_->waiting->num_pending();
}

template <class Pose>
void SessionStore<Pose>::RecordFirstKeyframe(
    PoseId id, const KeyframeRecord<Pose>& keyframe) {
  typename Impl::Pending row;
  row.kind = kFirstKeyframe;
  row.pose_id = id;
  row.keyframe = keyframe;
  impl_->pending.push_back(std::move(row));
}

template <class Pose>
void SessionStore<Pose>::RecordKeyframe(PoseId id,
                                        const KeyframeRecord<Pose>& keyframe,
                                        const Pose& odometry,
                                        const Information& information) {
  typename Impl::Pending row;
  row.kind = kKeyframe;
  row.pose_id = id;
  row.keyframe = keyframe;
  row.measurement = Encode(odometry);
  row.information = Encode(information);
  impl_->pending.push_back(std::move(row));
}

template <class Pose>
void SessionStore<Pose>::RecordCandidate(int number, PoseId a, PoseId b,
                                         const Pose& z,
                                         const Information& information) {
  typename Impl::Pending row;
  row.kind = kLoop;
  row.candidate = number;
  row.from = a;
  row.to = b;
  row.measurement = Encode(z);
  row.information = Encode(information);
  impl_->pending.push_back(std::move(row));
}

template <class Pose>
std::int64_t SessionStore<Pose>::RecordStampedWaiting(
    std::int64_t message, std::int64_t from_ns, std::int64_t to_ns,
    const Pose& z, const Information& information) {
  return impl_->waiting->Hold(message, from_ns, to_ns, z, information);
}

template <class Pose>
void SessionStore<Pose>::RecordStampedResolved(std::int64_t key) {
  impl_->waiting->Release(key);
}

template <class Pose>
void SessionStore<Pose>::CommitUpdate(
    bool finish, const std::vector<DecisionChange>& changes,
    const OnlineVerifier<Pose>* verifier) {
  SqliteDb& db = impl_->db;
  std::int64_t keyframes = impl_->keyframes_since_checkpoint;
  for (const auto& row : impl_->pending) keyframes += row.kind != kLoop;
  db.Execute("BEGIN IMMEDIATE");
  try {
    SqliteStatement& insert = *impl_->insert_input;
    std::int64_t seq = impl_->next_seq;
    for (const auto& row : impl_->pending) {
      insert.Bind(1, seq++);
      insert.Bind(2, static_cast<std::int64_t>(row.kind));
      if (row.kind == kLoop) {
        for (int column = 3; column <= 6; ++column) insert.BindNull(column);
        insert.Bind(7, static_cast<std::int64_t>(row.candidate));
        insert.Bind(8, row.from);
        insert.Bind(9, row.to);
      } else {
        insert.Bind(3, row.pose_id);
        insert.Bind(4, row.keyframe.stamp_ns);
        insert.Bind(5, Encode(row.keyframe.odometry_pose));
        insert.Bind(6, Encode(row.keyframe.covariance));
        for (int column = 7; column <= 9; ++column) insert.BindNull(column);
      }
      if (row.kind == kFirstKeyframe) {
        insert.BindNull(10);
        insert.BindNull(11);
      } else {
        insert.Bind(10, row.measurement);
        insert.Bind(11, row.information);
      }
      insert.Step();
      insert.Reset();
    }
    impl_->updates->Append(impl_->next_update, seq - 1, finish, changes);
    impl_->waiting->Write();
    if (verifier && impl_->checkpoint_keyframes > 0 &&
        keyframes >= impl_->checkpoint_keyframes) {
      const std::string state = verifier->SaveState();
      if (!state.empty()) {
        db.Execute("DELETE FROM checkpoint");
        SqliteStatement checkpoint(
            &db,
            "INSERT INTO checkpoint(update_number, last_seq, state) VALUES "
            "(?, ?, ?)");
        checkpoint.Bind(1, impl_->next_update);
        checkpoint.Bind(2, seq - 1);
        checkpoint.BindBlob(3, Compress(state));
        checkpoint.Step();
        keyframes = 0;
      }
    }
    db.Execute("COMMIT");
    impl_->keyframes_since_checkpoint = keyframes;
    impl_->next_seq = seq;
    ++impl_->next_update;
    impl_->pending.clear();
    impl_->waiting->Committed();
  } catch (...) {
    impl_->insert_input->Reset();
    impl_->updates->Reset();
    impl_->waiting->Failed();
    sqlite3_exec(db.handle(), "ROLLBACK", nullptr, nullptr, nullptr);
    throw;
  }
}

template <class Pose>
ResumeSummary SessionStore<Pose>::Resume(
    OnlineVerifier<Pose>* verifier,
    const std::function<void(PoseId, const KeyframeRecord<Pose>&)>& on_keyframe,
    const std::function<void(const StampedWaiting<Pose>&)>& on_waiting) {
  SqliteDb& db = impl_->db;
  const std::vector<UpdateRow> updates = ReadUpdates(&db);
  ResumeSummary summary;
  CheckpointRow checkpoint;
  bool restore = false;
  // Runs `use` on the checkpoint; what it throws fails the resume, naming it.
  const auto with_checkpoint = [&](const auto& use) {
    try {
      use();
    } catch (const std::runtime_error& e) {
      db.Fail("the checkpoint after update " +
              std::to_string(checkpoint.update_number) + ": " + e.what());
    }
  };
  if (ReadCheckpoint(&db, &checkpoint)) {
    with_checkpoint([&] {
      checkpoint.state = Decompress(checkpoint.state);
      restore = verifier->SavedUnderSameOptions(checkpoint.state);
    });
    summary.checkpoint_of_other_options = !restore;
  }
  // Restores the checkpoint, once the inputs up to its last_seq are in.
  const auto restore_checkpoint = [&] {
    with_checkpoint([&] { verifier->RestoreState(checkpoint.state); });
    summary.checkpoint_update = checkpoint.update_number;
    restore = false;
    impl_->keyframes_since_checkpoint = 0;
  };
  size_t next = 0;
  const auto run_updates_through = [&](std::int64_t seq) {
    for (; next < updates.size() && updates[next].last_seq <= seq; ++next) {
      ++summary.updates;
      if (restore && updates[next].number <= checkpoint.update_number) {
        continue;  // its work is in the checkpoint
      }
      if (restore) restore_checkpoint();
      if (updates[next].finish) {
        verifier->Finish();
      } else {
        verifier->Update();
      }
    }
    if (restore && seq == checkpoint.last_seq) restore_checkpoint();
  };
  run_updates_through(0);
  std::int64_t last_stamp_ns = std::numeric_limits<std::int64_t>::min();
  ForEachInput<Pose>(&db, [&](const InputRow<Pose>& row) {
    const std::string at = "input " + std::to_string(row.seq) + ": ";
    if (row.kind != kLoop) {
      if (row.keyframe.stamp_ns < last_stamp_ns) {
        db.Fail(at + "keyframe " + std::to_string(row.pose_id) +
                " is stamped before the keyframe it follows");
      }
      last_stamp_ns = row.keyframe.stamp_ns;
    }
    try {
      if (row.kind == kFirstKeyframe) {
        verifier->AddFirstPose(row.pose_id, row.keyframe.odometry_pose);
      } else if (row.kind == kKeyframe) {
        const PoseId id =
            verifier->AddOdometry(row.measurement, row.information);
        if (id != row.pose_id) {
          db.Fail(at + "keyframe " + std::to_string(row.pose_id) +
                  " does not follow keyframe " + std::to_string(id - 1));
        }
      } else {
        const int number = verifier->AddLoop(row.from, row.to, row.measurement,
                                             row.information);
        if (number != row.candidate) {
          db.Fail(at + "candidate " + std::to_string(row.candidate) +
                  " arrives as number " + std::to_string(number));
        }
        ++summary.candidates;
      }
      if (row.kind != kLoop && on_keyframe) {
        on_keyframe(row.pose_id, row.keyframe);
      }
    } catch (const std::logic_error& e) {  // incl. DegenerateCandidate
      db.Fail(at + e.what());
    }
    if (row.kind != kLoop) {
      ++summary.keyframes;
      ++impl_->keyframes_since_checkpoint;
    }
    run_updates_through(row.seq);
  });
  run_updates_through(std::numeric_limits<std::int64_t>::max());
  if (restore) {
    db.Fail("the checkpoint after update " +
            std::to_string(checkpoint.update_number) + " follows input " +
            std::to_string(checkpoint.last_seq) + ", which is not recorded");
  }
  for (const auto& [candidate, state] : ReadFinalStates(&db)) {
    if (candidate >= verifier->num_candidates() ||
        verifier->state(candidate) != state) {
      ++summary.differing_decisions;
    }
  }
  for (const StampedWaiting<Pose>& held : impl_->waiting->Read()) {
    ++summary.waiting_by_stamp;
    if (on_waiting) on_waiting(held);
  }
  return summary;
}

template class SessionStore<Pose2>;
template class SessionStore<Pose3>;

}  // namespace rrr
