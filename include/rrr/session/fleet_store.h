// A fleet's session database: its robots, each keyframe of each robot's
// sessions, the loop candidates within and between robots and each update
// with the decisions it changed, kept in SQLite so that a crash loses at most
// one update, and replayed into a new Fleet on resume.
#ifndef RRR_SESSION_FLEET_STORE_H_
#define RRR_SESSION_FLEET_STORE_H_

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "rrr/fleet/fleet.h"
#include "rrr/session/session_store.h"

namespace rrr {

// The schema version of a fleet's database this library writes and reads.
constexpr int kFleetSchemaVersion = 1;

// What FleetStore::Resume found and did.
struct FleetResumeSummary {
  int keyframes = 0;
  int sessions = 0;    // recorded sessions, over every robot
  int candidates = 0;  // recorded candidates (some may wait for robots)
  int updates = 0;
  // Candidates whose replayed state differs from the recorded one: 0 when
  // the options are the same and rules 1–5 between chains ran inside the
  // updates; with them in the background, the recording may not have taken
  // the last run's decisions yet (never otherwise at Finish()).
  int differing_decisions = 0;
};

// Records a Fleet's inputs as they are taken and its decisions at each
// update, in an SQLite database (WAL journal); what is recorded between two
// updates is written in one transaction by CommitUpdate. The database names
// its robots: a resume with robots added is fine, one without a recorded
// robot fails. Not thread-safe: one owner (the fleet's thread) calls every
// method.
template <class Pose>
class FleetStore {
 public:
  using Information = typename Constraint<Pose>::Information;

  // Opens the database at `path`, creating it if it does not exist, for a
  // fleet of `robots` judged by `procedure`. Throws SessionError naming the
  // file if it is not a fleet's database of this version, was recorded in
  // the other dimension or by another procedure, or cannot be written.
  FleetStore(const std::string& path, const std::vector<std::string>& robots,
             const std::string& procedure);
  ~FleetStore();
  FleetStore(const FleetStore&) = delete;
  FleetStore& operator=(const FleetStore&) = delete;

  // Feeds the recording to `fleet`, which must be new and name every
  // recorded robot, in the order it was recorded: each keyframe as the
  // fleet took it (Fleet::AddKeyframe, its sessions as they were), each
  // candidate, and Fleet::Update() or Finish() where the recording ran them
  // (each keyframe must come back under its recorded id and each candidate
  // under its recorded number): the decisions are those the recording had
  // after its last update. Then
  // every robot that has a session starts a new one with its next reading
  // (a node started again cannot know where its robots went meanwhile; only
  // loop closures join what comes next to what was). Throws SessionError
  // naming the database and the input that cannot be replayed.
  FleetResumeSummary Resume(Fleet<Pose>* fleet);

  // Records a keyframe the fleet took from robot `robot` (its index in the
  // robots given at construction): what Fleet::AddReading made of it.
  void RecordKeyframe(int robot, const KeyframeRecord<Pose>& keyframe,
                      const typename Fleet<Pose>::Taken& taken);
  // Records a candidate the fleet took, with the number it gave it (-1: it
  // waits for a robot or a keyframe near a stamp).
  void RecordCandidate(int number, int robot_a, std::int64_t id_a, int robot_b,
                       std::int64_t id_b, const Pose& z,
                       const Information& information);
  // The same for a candidate named by stamps (Fleet::AddLoopByStamp).
  void RecordCandidateByStamp(int number, int robot_a, std::int64_t stamp_a,
                              int robot_b, std::int64_t stamp_b, const Pose& z,
                              const Information& information);
  // Writes what was recorded since the last commit and the update that
  // followed it (`finish`: a Finish()) with its changes, in one transaction.
  // Throws SessionError if the database cannot be written.
  void CommitUpdate(bool finish, const std::vector<DecisionChange>& changes);

  // Inputs recorded and not yet committed.
  int num_uncommitted() const;
  const std::string& path() const;

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

// True if the session database at `path` is a fleet's (else it is one
// robot's, or not one; see LooksLikeSessionDatabase).
bool IsFleetDatabase(const std::string& path);

}  // namespace rrr

#endif  // RRR_SESSION_FLEET_STORE_H_
