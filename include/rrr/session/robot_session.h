// One robot's verification over time, as rrr_node runs it, without ROS.
#ifndef RRR_SESSION_ROBOT_SESSION_H_
#define RRR_SESSION_ROBOT_SESSION_H_

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "rrr/graph/candidate_defect.h"
#include "rrr/graph/keyframe_track.h"
#include "rrr/graph/odometry_input.h"
#include "rrr/graph/stamped_candidates.h"
#include "rrr/rrr/online_verifier.h"
#include "rrr/rrr/options.h"
#include "rrr/session/session_store.h"

namespace rrr {

struct RobotSessionOptions {
  RrrOptions rrr;  // the decision procedure (map or published) and its options
  OdometryInputOptions odometry;
  // The session database (SessionStore): every input and decision is
  // recorded there as it comes, and Resume() takes up what it holds. Empty:
  // none.
  std::string database;
  // Keyframes between two checkpoints of the verifier's state in the
  // database (SessionStore; 0: none).
  int checkpoint_keyframes = kDefaultCheckpointKeyframes;
  // A keyframe back at its odometry frame's origin while the newest one was
  // more than this many metres from it: the odometry restarted at zero (a
  // driver started again), and the keyframe is joined to the one before by
  // that jump, an odometry edge that never happened (Taken::restarted;
  // one chain has no other way; a fleet of one robot starts a session).
  // 0: not looked for.
  double restart_jump = 1.0;
};

// A loop candidate message that a RobotSession could not take, and why.
struct SkippedMessage {
  std::int64_t message = 0;  // the caller's number of it
  CandidateDefect defect = CandidateDefect::kUnknownPose;
  std::string why;
};

// One robot: its odometry readings become the keyframes and odometry edges
// of one chain, its loop candidates (named by keyframe id, or by stamp and
// held until the keyframes near the stamps exist) go to the decision
// procedure (MapVerifier or IncrementalVerifier), and the keyframes'
// corrected poses follow the decisions. With a database, every input and
// update is recorded as it happens, so that a session opened again on it
// takes up where the last one stopped. Nothing is dropped silently: a reading
// that cannot be taken says why (Taken::problem), a candidate that cannot
// goes to the `on_skip` callback with its reason. Not thread-safe: one owner
// calls every method.
template <class Pose>
class RobotSession {
 public:
  using Information = typename Constraint<Pose>::Information;
  using OnSkip = std::function<void(const SkippedMessage&)>;

  // Throws std::invalid_argument for options that do not validate
  // (RrrOptions::Validate, NoiseModelOf, TrackOf).
  RobotSession(const RobotSessionOptions& options, OnSkip on_skip);
  ~RobotSession();

  // Opens the database of the options (none: does nothing) and replays what
  // it recorded: the keyframes, the candidates, those waiting by stamp and
  // the updates (SessionStore::Resume). Call it before any input. Throws
  // SessionError naming the file if it cannot be opened or replayed.
  ResumeSummary Resume();

  // What AddReading made of a reading.
  struct Taken {
    std::string problem;  // why it was refused; "" if it was not
    // Stamped at or before the newest keyframe a resumed database held: it
    // was taken before the session stopped (a bag played again from its
    // start), and is not taken again.
    bool already_recorded = false;
    bool keyframe = false;  // it became keyframe `id`
    PoseId id = -1;
    // For a keyframe after the first: its odometry edge's information came
    // from the readings' covariance change (else from the motion).
    bool information_from_covariance = false;
    // The keyframe is the first after the odometry restarted at zero
    // (RobotSessionOptions::restart_jump): its edge is `jump` long.
    bool restarted = false;
    double jump = 0.0;  // m
  };
  // Takes the robot's next odometry reading. A new keyframe is added to the
  // verifier (and recorded), and the candidates waiting by stamp that it
  // settles are added or skipped.
  Taken AddReading(const KeyframeRecord<Pose>& reading);
  // Takes the candidate `z` (with `information`) of message `message`
  // between keyframes `from` and `to`; a keyframe that does not exist yet is
  // waited for (OnlineVerifier::AddLoop), a degenerate candidate skipped.
  void AddCandidate(std::int64_t message, PoseId from, PoseId to, const Pose& z,
                    const Information& information);
  // As AddCandidate, between the keyframes nearest the stamps `from_ns` and
  // `to_ns` within the stamp tolerance: held until both can be found, then
  // added, or skipped if no keyframe is near one of them (or if
  // RrrOptions::max_waiting candidates wait by stamp already).
  void AddCandidateByStamp(std::int64_t message, std::int64_t from_ns,
                           std::int64_t to_ns, const Pose& z,
                           const Information& information);

  // What Update made.
  struct Updated {
    std::vector<DecisionChange> changes;
    bool accepted_changed = false;  // a loop entered or left the accepted set
    // Why the database could not record the update ("" if it did, or if
    // there is none). The session goes on without it.
    std::string store_error;
  };
  // Runs the procedure's Update() (Finish() if `finish`: every pending
  // cluster judged now) and records it with the inputs since the last one.
  Updated Update(bool finish);

  const OnlineVerifier<Pose>& verifier() const { return *verifier_; }
  const KeyframeTrack<Pose>& keyframes() const { return keyframes_; }
  int waiting_by_stamp() const { return stamped_waiting_.size(); }
  // The keyframes' corrected poses in the map frame (the first keyframe's
  // odometry frame), brought up to date with the decisions first.
  const std::vector<Pose>& Map();
  // The map → odometry frame correction of the newest keyframe; up to date
  // after every Update().
  Pose MapToOdom() const { return keyframes_.MapToOdom(); }

 private:
  // After the accepted loops changed: the newest keyframe's correction now,
  // the whole map when it is next asked for.
  void MapChanged();
  void ResolveStampedLoops();
  void Skip(std::int64_t message, CandidateDefect defect,
            const std::string& why);

  const RobotSessionOptions options_;
  const OnSkip on_skip_;
  std::unique_ptr<OnlineVerifier<Pose>> verifier_;
  std::unique_ptr<SessionStore<Pose>> store_;  // with a database
  const OdometryNoiseModel<Pose> odometry_noise_;
  KeyframeTrack<Pose> keyframes_;  // and their corrected poses
  bool map_stale_ = false;         // keyframes_'s map is behind the verifier's
  StampedCandidates<StampedWaiting<Pose>> stamped_waiting_;
  // Readings stamped at or before this were taken before a Resume().
  std::int64_t resumed_until_ns_ = 0;
  bool resumed_ = false;
};

}  // namespace rrr

#endif  // RRR_SESSION_ROBOT_SESSION_H_
