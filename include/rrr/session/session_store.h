// A robot's session on disk: what a verifier was given and what it decided,
// kept in an SQLite database so that a crash loses at most one update.
#ifndef RRR_SESSION_SESSION_STORE_H_
#define RRR_SESSION_SESSION_STORE_H_

#include <cstdint>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "rrr/graph/keyframe_track.h"
#include "rrr/io/g2o.h"
#include "rrr/rrr/online_verifier.h"

namespace rrr {

// A session database that cannot be used: what() reads "PATH: PROBLEM".
class SessionError : public std::runtime_error {
 public:
  SessionError(const std::string& path, const std::string& problem)
      : std::runtime_error(path + ": " + problem) {}
};

// The schema version this library writes. It reads this one and versions 1
// (which had no candidates waiting by stamp) and 2 (no checkpoint), and
// brings an older database it opens to record (SessionStore) up to this one.
constexpr int kSessionSchemaVersion = 3;

// Keyframes between two checkpoints of a session by default (SessionStore).
constexpr int kDefaultCheckpointKeyframes = 1000;

// What Resume found and did.
struct ResumeSummary {
  int keyframes = 0;
  int candidates = 0;
  int updates = 0;  // recorded, whether run again or restored
  // The update whose saved state was restored (0: none, every update was
  // run again).
  std::int64_t checkpoint_update = 0;
  // A checkpoint was found but not restored: it was saved under other
  // options, so every update was run again.
  bool checkpoint_of_other_options = false;
  // Candidates whose replayed state differs from the recorded one (0 unless
  // the verifier's options changed between the runs).
  int differing_decisions = 0;
  // Candidates named by stamp that were waiting for keyframes.
  int waiting_by_stamp = 0;
};

// A loop candidate named by the stamps (ns) of its poses, waiting for
// keyframes near them, under the key SessionStore gave it.
template <class Pose>
struct StampedWaiting {
  std::int64_t key = 0;
  std::int64_t message = 0;  // the caller's number of it (e.g. a header seq)
  std::int64_t from_ns = 0, to_ns = 0;
  Pose measurement;
  typename Constraint<Pose>::Information information;
};

// The inputs of an OnlineVerifier and its decisions, recorded as they happen
// in an SQLite database (WAL journal): the keyframes with their odometry
// edges, the loop candidates in arrival order, each update with the
// decisions it changed, and the candidates named by stamp that wait for
// keyframes (held outside the verifier). What is recorded between two updates
// is written in one transaction by CommitUpdate, so after a crash the database
// holds every finished update and nothing of the unfinished one. Not
// thread-safe: one owner (the verifier's thread) calls every method.
template <class Pose>
class SessionStore {
 public:
  using Information = typename Constraint<Pose>::Information;

  // Opens the database at `path`, creating it (with the schema) if it does
  // not exist. `procedure` names the decision procedure that writes it.
  // Every `checkpoint_keyframes` keyframes (0: never), CommitUpdate saves the
  // verifier's state with the update, so that Resume need not run every
  // update again. Throws SessionError naming the file if it is not a session
  // database, if its schema version is not one this library reads, or if it
  // was recorded in the other dimension or with another procedure.
  SessionStore(const std::string& path, const std::string& procedure,
               int checkpoint_keyframes = kDefaultCheckpointKeyframes);
  ~SessionStore();
  SessionStore(const SessionStore&) = delete;
  SessionStore& operator=(const SessionStore&) = delete;

  // Feeds the recorded session to `verifier`, which must be new, in the order
  // it was recorded, running Update() (or Finish()) where the recording ran
  // one, except that the updates up to the checkpoint are not run again: the
  // verifier's state saved there is restored after the inputs it had seen
  // (unless it was saved under other options). Calls `on_keyframe` with
  // each keyframe's id and record in order
  // (a std::logic_error it throws, such as std::invalid_argument, fails the
  // resume with a SessionError naming the input). Compares the replayed
  // decisions with the recorded ones. Then calls `on_waiting` (if given)
  // with each candidate that waited by stamp at the last commit, by key.
  ResumeSummary Resume(
      OnlineVerifier<Pose>* verifier,
      const std::function<void(PoseId, const KeyframeRecord<Pose>&)>&
          on_keyframe,
      const std::function<void(const StampedWaiting<Pose>&)>& on_waiting =
          nullptr);

  // Records the first keyframe (pose `id`), then each further keyframe
  // with the odometry edge from the previous one, and each candidate as
  // OnlineVerifier::AddLoop numbered it. Held in memory until CommitUpdate.
  void RecordFirstKeyframe(PoseId id, const KeyframeRecord<Pose>& keyframe);
  void RecordKeyframe(PoseId id, const KeyframeRecord<Pose>& keyframe,
                      const Pose& odometry, const Information& information);
  void RecordCandidate(int number, PoseId a, PoseId b, const Pose& z,
                       const Information& information);
  // Records that a candidate named by the stamps `from_ns` and `to_ns`
  // waits for keyframes, numbered `message` by the caller; returns its key
  // (each larger than any before).
  std::int64_t RecordStampedWaiting(std::int64_t message, std::int64_t from_ns,
                                    std::int64_t to_ns, const Pose& z,
                                    const Information& information);
  // Records that the candidate under `key` waits no more (it was added as a
  // candidate, recorded with RecordCandidate, or refused).
  void RecordStampedResolved(std::int64_t key);
  // Writes what was recorded since the last commit and the update that
  // followed it (`finish`: a Finish()) with its changes, in one transaction;
  // with them, once `checkpoint_keyframes` keyframes were committed since
  // the last checkpoint, the state of `verifier` (if given, and if it saves
  // one), which replaces the last checkpoint. Throws SessionError if the
  // database cannot be written.
  void CommitUpdate(bool finish, const std::vector<DecisionChange>& changes,
                    const OnlineVerifier<Pose>* verifier = nullptr);

  // Inputs recorded and not yet committed.
  int num_uncommitted() const;
  const std::string& path() const;

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

// A session database read back as a pose graph: the keyframes (estimates
// composed from the odometry), the odometry edges, the candidates whose poses
// exist as loops in arrival order, and each loop's last recorded state.
struct SessionContents {
  AnyPoseGraph graph;
  std::vector<LoopState> loop_states;  // by loop index of `graph`
  std::string procedure;
  int updates = 0;  // recorded, whether run again or restored
  // The update whose saved state was restored (0: none, every update was
  // run again).
  std::int64_t checkpoint_update = 0;
  // A checkpoint was found but not restored: it was saved under other
  // options, so every update was run again.
  bool checkpoint_of_other_options = false;
  int candidates_waiting = 0;  // candidates naming a pose never recorded
  int waiting_by_stamp = 0;    // candidates named by stamp, waiting
};

// Reads the session database at `path` (read only). Throws SessionError
// naming the file for anything but a complete session database of this
// schema version (a corrupt file, another format, bad values).
SessionContents ReadSession(const std::string& path);

// True if the file at `path` starts as an SQLite database does.
bool LooksLikeSessionDatabase(const std::string& path);

}  // namespace rrr

#endif  // RRR_SESSION_SESSION_STORE_H_
