// What a verifier node keeps over time, for one robot or a fleet, without
// ROS: each robot's readings and sessions, the loop candidates, the decision
// procedure and the session database.
#ifndef RRR_SESSION_SESSION_H_
#define RRR_SESSION_SESSION_H_

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rrr/graph/candidate_defect.h"
#include "rrr/graph/keyframe_track.h"
#include "rrr/graph/odometry_input.h"
#include "rrr/graph/odometry_noise.h"
#include "rrr/graph/stamped_candidates.h"
#include "rrr/rrr/online_verifier.h"
#include "rrr/rrr/options.h"
#include "rrr/session/session_store.h"

namespace rrr {

struct SessionOptions {
  RrrOptions rrr;  // the decision procedure (map or published) and its options
  // How each robot's readings become keyframes and odometry edges.
  OdometryInputOptions odometry;
  // A reading back at its odometry frame's origin while the robot's last
  // reading was more than this many metres from it: its odometry restarted
  // (a driver started again). 0: not looked for.
  double restart_jump = 1.0;
  // The session database (SessionStore): every input and update is recorded
  // there as it comes, and Resume() takes up what it holds. Empty: none.
  std::string database;
  // Keyframes between two checkpoints of the procedure's state in the
  // database (0: none).
  int checkpoint_keyframes = kDefaultCheckpointKeyframes;
};

// A keyframe of a session: the odometry chain (session) it is in, and its id
// among its robot's keyframes.
struct ChainPose {
  int chain = 0;
  PoseId id = 0;
};

// A loop candidate a Session could not take, and why.
struct SkippedMessage {
  std::int64_t message = 0;  // the caller's number of it
  CandidateDefect defect = CandidateDefect::kUnknownPose;
  std::string why;
};

// The robots named at construction (one, whose name may be empty, or a
// fleet), each with its sessions: a session is one odometry chain of the
// decision procedure, joined to the others only by loop closures, never by
// an odometry edge that did not happen. A robot's first reading starts its
// first session; a reading stamped before its last, or back at its odometry
// frame's origin far from it (SessionOptions::restart_jump), starts another
// (the published procedure judges one chain: there the restart is joined by
// its jump, and Taken::restarted says so). A robot's keyframes are numbered
// 0, 1, ... over all its sessions. Candidates name robot and keyframe at
// both ends, by id or by stamp; one that cannot be taken goes to the
// `on_skip` callback with its reason, now or when it is settled. With a
// database, every input and update is recorded as it happens, so that a
// session opened again on it takes up where the last one stopped: each
// robot's readings stamped at or before its last recorded one are not taken
// again, and the next continue its session (or start one, by the rule
// above). With a database, Resume() comes before any input. Not
// thread-safe: one owner calls every method.
template <class Pose>
class Session {
 public:
  using Information = typename Constraint<Pose>::Information;
  using OnSkip = std::function<void(const SkippedMessage&)>;

  // Throws std::invalid_argument for no robot, a name repeated or (of
  // several) empty, the published procedure with several robots, or
  // options that do not validate.
  Session(std::vector<std::string> robots, const SessionOptions& options,
          OnSkip on_skip);
  ~Session();

  // Opens the database of the options (none: does nothing) and replays what
  // it recorded (SessionStore::Resume). Call it before any input. Throws
  // SessionError naming the file if it cannot be opened or replayed.
  ResumeSummary Resume();

  // What AddReading made of a reading.
  struct Taken {
    std::string problem;  // why it was refused; "" if it was not
    // Stamped at or before the robot's newest reading a resumed database
    // held: taken before the session stopped, not taken again.
    bool already_recorded = false;
    bool keyframe = false;     // it became keyframe `id` of chain `chain`
    bool new_session = false;  // it started chain `chain`
    PoseId id = -1;
    int chain = -1;
    // For a keyframe of a session after its first: its odometry edge's
    // information came from the readings' covariance change (else from the
    // motion).
    bool information_from_covariance = false;
    // The odometry restarted and the published procedure joined the
    // keyframe to the one before by that jump, `jump` m long.
    bool restarted = false;
    double jump = 0.0;
    // The information of its odometry edge (none for a session's first).
    Information information = Information::Zero();
  };
  // Takes robot `robot`'s next odometry reading (its pose in the robot's
  // odometry frame). Throws std::out_of_range for a robot that does not
  // exist.
  Taken AddReading(int robot, const KeyframeRecord<Pose>& reading);
  // Takes `keyframe` as the robot's next keyframe as AddReading took it (a
  // resume replays them so): the first of a new session if `new_session`,
  // else with an odometry edge of `information` if given (else of the
  // odometry options' noise model).
  Taken AddKeyframe(int robot, const KeyframeRecord<Pose>& keyframe,
                    bool new_session, const Information* information = nullptr);
  // Takes the candidate z ≈ x_a⁻¹ · x_b of message `message` between
  // keyframe `id_a` of robot `robot_a` and `id_b` of `robot_b`. A keyframe
  // not there yet is taken as one of the robot's current session (it waits
  // for it); a robot without a keyframe yet is waited for. Throws
  // std::out_of_range for a robot that does not exist.
  void AddCandidate(std::int64_t message, int robot_a, PoseId id_a, int robot_b,
                    PoseId id_b, const Pose& z, const Information& information);
  // As AddCandidate, between the robots' keyframes nearest the stamps
  // `stamp_a` and `stamp_b` (ns, within the stamp tolerance, in the newest
  // of the robot's sessions that has one): held until both can be found.
  void AddCandidateByStamp(std::int64_t message, int robot_a,
                           std::int64_t stamp_a, int robot_b,
                           std::int64_t stamp_b, const Pose& z,
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

  const std::vector<std::string>& robots() const { return robots_; }
  // Index of robot `name`, or -1.
  int RobotIndex(const std::string& name) const;
  // The decision procedure; its candidate numbers are the session's.
  const OnlineVerifier<Pose>& verifier() const { return *verifier_; }
  int num_chains() const { return static_cast<int>(chains_.size()); }
  int robot_of_chain(int chain) const { return chains_.at(chain).robot; }
  // The robot's sessions (chains), oldest first.
  const std::vector<int>& sessions(int robot) const {
    return sessions_.at(robot);
  }
  // The keyframes of chain `chain`.
  int ChainSize(int chain) const { return chains_.at(chain).track.size(); }
  int num_keyframes() const { return verifier_->graph().num_poses(); }
  // Candidates waiting by stamp, and for a robot's first keyframe.
  int num_waiting_by_stamp() const { return by_stamp_.size(); }
  int num_waiting_for_robots() const {
    return static_cast<int>(for_robots_.size());
  }
  // The candidate's ends (its sessions found), and the id of the keyframe as
  // of which it was decided (-1 while it is not).
  ChainPose from(int candidate) const { return ends_.at(candidate).first; }
  ChainPose to(int candidate) const { return ends_.at(candidate).second; }
  PoseId DecidedAt(int candidate) const;

  // The map chain `chain` is in: the lowest chain joined with it (itself if
  // none). The map a robot's current session is in, or -1 before its first
  // reading.
  int MapOfChain(int chain) const { return verifier_->MapOfChain(chain); }
  int MapOfRobot(int robot) const;
  // The transform from the robot's odometry frame to its map's frame (the
  // correction of its newest keyframe), as of the last Update(); nothing
  // before its first keyframe.
  std::optional<Pose> MapToOdom(int robot) const;
  // The corrected poses of the robot's keyframes of the sessions in map
  // `map`, oldest first, and their stamps.
  std::vector<Pose> Path(int robot, int map);
  std::vector<std::int64_t> PathStamps(int robot, int map) const;
  // The corrected pose of keyframe `pose` in its map's frame, if it exists.
  std::optional<Pose> Corrected(const ChainPose& pose);
  // Every chain in order (ids counted on over the chains, a gap of one id
  // between two), at the corrected poses, their odometry and every loop
  // that has both poses, in the order it entered the procedure's graph;
  // `candidate_of_loop`, if given, receives each loop's candidate number,
  // and `index_of_pose` each of the procedure's poses' index in the graph.
  PoseGraph<Pose> Graph(std::vector<int>* candidate_of_loop = nullptr,
                        std::vector<int>* index_of_pose = nullptr);
  // The accepted graph of map `map` (a chain), as Graph() lays it out: its
  // keyframes, their odometry and the accepted loops between them, with
  // each pose's robot and keyframe id.
  struct MapGraph {
    PoseGraph<Pose> graph;
    std::vector<int> robot;
    std::vector<PoseId> keyframe;
  };
  MapGraph AcceptedGraph(int map);

 private:
  struct Chain {
    int robot;
    PoseId first_id;
    PoseId base;  // the procedure's id of keyframe id k is base + k
    KeyframeTrack<Pose> track;
  };
  struct Waiting {
    std::int64_t message;
    int robot_a, robot_b;
    PoseId a, b;  // ids, or stamps (ns)
    Pose z;
    Information information;
  };
  // The chain of robot `robot` holding keyframe `id` (the current one for an
  // id past its newest).
  const Chain& ChainHolding(int robot, PoseId id) const;
  void Skip(std::int64_t message, CandidateDefect defect,
            const std::string& why);
  // Throws std::logic_error for an input before Resume() with a database:
  // it would not be recorded.
  void RequireResumed() const;
  // Adds the candidates that waited for robots that have keyframes now, and
  // those by stamp whose keyframes are settled.
  void AddWaiting();
  // Brings the corrected poses up to date with the decisions.
  void RefreshMap();

  std::vector<std::string> robots_;
  SessionOptions options_;
  OnSkip on_skip_;
  std::unique_ptr<OnlineVerifier<Pose>> verifier_;
  std::unique_ptr<SessionStore<Pose>> store_;  // with a database
  OdometryNoiseModel<Pose> noise_;
  std::vector<Chain> chains_;
  std::vector<std::vector<int>> sessions_;  // chains, by robot
  std::vector<PoseId> next_id_;             // by robot
  std::vector<std::optional<KeyframeRecord<Pose>>> last_reading_;  // by robot
  std::vector<std::int64_t> resumed_until_ns_;                     // by robot
  std::vector<std::pair<ChainPose, ChainPose>> ends_;  // by candidate
  std::vector<Waiting> for_robots_;                    // in arrival order
  StampedCandidates<Waiting> by_stamp_;
  std::vector<Pose> map_;  // the procedure's Map(), once asked for
  bool map_stale_ = true;
  // Resume() runs: inputs are recorded and skips were told before.
  bool replaying_ = false;
  bool resolving_ = false;  // AddWaiting() adds candidates recorded before
  bool Recording() const { return store_ && !replaying_ && !resolving_; }
};

// The session recorded in the database at `path` (ReadSessionDatabase names
// its robots, dimension and procedure) taken up by a new session of its
// robots under `options` with the recorded procedure, whose database is a copy
// of it at `copy` (the recording itself is not written to; the caller removes
// the copy, with its "-wal" file). Throws SessionError naming `path` if it
// cannot be read or replayed.
template <class Pose>
std::unique_ptr<Session<Pose>> ReplaySession(const std::string& path,
                                             const std::string& copy,
                                             SessionOptions options);

}  // namespace rrr

#endif  // RRR_SESSION_SESSION_H_
