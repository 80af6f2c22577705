// A session on disk: what the robots gave and what was decided, kept in an
// SQLite database so that a crash loses at most one update.
#ifndef RRR_SESSION_SESSION_STORE_H_
#define RRR_SESSION_SESSION_STORE_H_

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "rrr/graph/keyframe_track.h"
#include "rrr/graph/pose_graph.h"
#include "rrr/rrr/online_verifier.h"
#include "rrr/rrr/options.h"

namespace rrr {

template <class Pose>
class Session;

// A session database that cannot be used: what() reads "PATH: PROBLEM".
class SessionError : public std::runtime_error {
 public:
  SessionError(const std::string& path, const std::string& problem)
      : std::runtime_error(path + ": " + problem) {}
};

// The schema version this library writes and reads. Earlier versions (1 to
// 3: one robot's inputs; a fleet's version 1) are refused, naming theirs.
constexpr int kSessionSchemaVersion = 4;

// Keyframes between two checkpoints of a session by default (SessionStore).
constexpr int kDefaultCheckpointKeyframes = 1000;

// What Resume found and did.
struct ResumeSummary {
  int keyframes = 0;
  int sessions = 0;    // over every robot
  int candidates = 0;  // recorded, by id or by stamp
  int updates = 0;     // recorded, whether run again or restored
  // The update whose saved state was restored (0: none, every update was
  // run again).
  std::int64_t checkpoint_update = 0;
  // A checkpoint was found but not restored: it was saved under other
  // options, so every update was run again.
  bool checkpoint_of_other_options = false;
  // Candidates whose replayed state differs from the recorded one (0 unless
  // the options changed between the runs).
  int differing_decisions = 0;
};

// What a session database holds before it is replayed.
struct SessionDatabase {
  std::vector<std::string> robots;  // recorded, in order
  int dimension = 2;                // 2 or 3
  RrrOptions options;               // the options it was recorded under
};

// Why `robots` cannot name a session's robots ("" if they can): none, a
// name twice, or an empty name among several.
std::string RobotNamesProblem(const std::vector<std::string>& robots);

// Reads what the session database at `path` was recorded for (read only).
// Throws SessionError naming the file if it is not a session database of
// this schema version, its robots are not a session's (RobotNamesProblem),
// or its options are not usable or cannot judge its robots.
SessionDatabase ReadSessionDatabase(const std::string& path);

// True if the file at `path` starts as an SQLite database does.
bool LooksLikeSessionDatabase(const std::string& path);

// The inputs a Session took and its decisions, recorded as they happen in an
// SQLite database (WAL journal): its robots, each keyframe with the session
// it started or continued, each candidate (by keyframe ids or by stamps) in
// arrival order, and each update with the decisions it changed. What is
// recorded between two updates is written in one transaction by
// CommitUpdate, so after a crash the database holds every finished update
// and nothing of the unfinished one. The database names its robots: a
// resume with robots added is fine, one without a recorded robot fails.
// Not thread-safe: one owner (the session's thread) calls every method.
template <class Pose>
class SessionStore {
 public:
  using Information = typename Constraint<Pose>::Information;

  // Opens the database at `path`, creating it if it does not exist, for the
  // robots `robots` judged under `options` (recorded when it is created). Every
  // `checkpoint_keyframes` keyframes (0: never), CommitUpdate saves the
  // procedure's state with the update, so that Resume need not run every update
  // again. Throws SessionError naming the file if it is not a session database
  // of this schema version, was recorded in the other dimension or by another
  // procedure, or cannot be written.
  SessionStore(const std::string& path, const std::vector<std::string>& robots,
               const RrrOptions& options, int checkpoint_keyframes);
  ~SessionStore();
  SessionStore(const SessionStore&) = delete;
  SessionStore& operator=(const SessionStore&) = delete;

  // Feeds the recording to `session` (new, naming every recorded robot) in
  // the order it was recorded: each keyframe as it took it
  // (Session::AddKeyframe), each candidate, and Update() or Finish() of its
  // procedure `verifier` where the recording ran one, except that the
  // updates up to the checkpoint are not run again: the state saved there
  // is restored after the inputs it had seen (unless it was saved under
  // other options). Compares the replayed decisions with the recorded ones.
  // Throws SessionError naming the database and the input that cannot be
  // replayed.
  ResumeSummary Resume(Session<Pose>* session, OnlineVerifier<Pose>* verifier);

  // Records a keyframe the session took from robot `robot` (its index among
  // the robots given at construction): the first of a new session or the
  // next of the robot's current one, its id and its odometry edge's
  // information.
  template <class Taken>
  void RecordKeyframe(int robot, const KeyframeRecord<Pose>& keyframe,
                      const Taken& taken) {
    Keyframe(robot, keyframe, taken.new_session, taken.id, taken.information);
  }
  // Records a candidate the session took (message `message`), between
  // keyframe ids, or stamps if `by_stamp`.
  void RecordCandidate(std::int64_t message, int robot_a, std::int64_t a,
                       int robot_b, std::int64_t b, const Pose& z,
                       const Information& information, bool by_stamp);
  // Writes what was recorded since the last commit and the update that
  // followed it (`finish`: a Finish()) with its changes, in one
  // transaction; with them, once `checkpoint_keyframes` keyframes were
  // committed since the last checkpoint, the state of `verifier` (if it
  // saves one), which replaces the last checkpoint. Throws SessionError if
  // the database cannot be written.
  void CommitUpdate(bool finish, const std::vector<DecisionChange>& changes,
                    const OnlineVerifier<Pose>* verifier);

  // Inputs recorded and not yet committed.
  int num_uncommitted() const;
  const std::string& path() const;

 private:
  void Keyframe(int robot, const KeyframeRecord<Pose>& keyframe,
                bool new_session, std::int64_t id,
                const Information& information);

  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rrr

#endif  // RRR_SESSION_SESSION_STORE_H_
