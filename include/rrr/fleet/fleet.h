// A fleet of robots as a verifier node sees them: each robot's odometry
// readings, its sessions and keyframes, and the loop candidates within and
// between robots, judged by one MapVerifier over their chains. Nothing here
// knows ROS.
#ifndef RRR_FLEET_FLEET_H_
#define RRR_FLEET_FLEET_H_

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "rrr/graph/keyframe_track.h"
#include "rrr/graph/odometry_input.h"
#include "rrr/graph/odometry_noise.h"
#include "rrr/graph/stamped_candidates.h"
#include "rrr/rrr/map/map_verifier.h"
#include "rrr/rrr/options.h"

namespace rrr {

// How a fleet turns readings into keyframes and sessions.
struct FleetOptions {
  RrrOptions rrr;
  // How each robot's readings become keyframes and odometry edges.
  OdometryInputOptions odometry;
  // A reading that moved more than this many metres from the robot's last
  // reading (not keyframe) is no motion a robot makes between two readings:
  // its odometry restarted (at zero, typically) and it starts a new
  // session. 0 turns the test off.
  double restart_jump = 1.0;
};

// A keyframe of a fleet: the chain (session) it is in and its id in its
// robot.
struct ChainPose {
  int chain = 0;
  PoseId id = 0;
};

// The accepted graph of one map of a fleet (Fleet::AcceptedGraph).
template <class Pose>
struct FleetGraph {
  // The keyframes of the sessions in the map, in chain order, at their
  // corrected poses, under the ids of Fleet::Graph() (every chain, a gap of
  // one id between two); their odometry and the accepted loops between
  // them.
  PoseGraph<Pose> graph;
  std::vector<int> robot;              // of each pose
  std::vector<std::int64_t> keyframe;  // of each pose: its id in its robot
};

// The robots named at construction, each with its sessions: a session is one
// odometry chain of the verifier, joined to the others only by loop closures
// (never by an odometry edge that did not happen). A robot's keyframes are
// numbered 0, 1, ... over all its sessions; a candidate names robot and
// keyframe at both ends.
template <class Pose>
class Fleet {
 public:
  using Information = typename Constraint<Pose>::Information;

  // What AddReading made of a reading.
  struct Taken {
    std::string problem;       // why it was refused; "" if it was not
    bool keyframe = false;     // it became a keyframe (id `id`)
    bool new_session = false;  // it started a session (of `chain`)
    std::int64_t id = -1;
    int chain = -1;
  };

  // Throws std::invalid_argument for no robot, a name repeated or empty, or
  // options that do not validate (a negative restart_jump, odometry
  // options NoiseModelOf or TrackOf refuses).
  Fleet(std::vector<std::string> robots, const FleetOptions& options);

  // Index of robot `name`, or -1.
  int RobotIndex(const std::string& name) const;
  const std::vector<std::string>& robots() const { return robots_; }

  // Takes robot `robot`'s next odometry reading (its pose in the robot's
  // odometry frame). The first reading, one after StartSession(), one
  // stamped before the robot's last reading, or one further than
  // restart_jump from it starts a new session. Throws std::out_of_range for
  // a robot that does not exist.
  Taken AddReading(int robot, const KeyframeRecord<Pose>& reading);
  // Takes `keyframe` as the robot's next keyframe, as AddReading made one
  // (to replay a recording): the first of a new session if `new_session`,
  // else the next of its current session, whatever it moved. Throws
  // std::logic_error for `new_session` false and no session yet.
  Taken AddKeyframe(int robot, const KeyframeRecord<Pose>& keyframe,
                    bool new_session);
  // The robot's next reading starts a new session (a restart the odometry
  // does not show, as after a node restart).
  void StartSession(int robot);

  // Adds the candidate z ≈ x_a⁻¹ · x_b between keyframe `id_a` of robot
  // `robot_a` and `id_b` of `robot_b` and returns its number. A keyframe not
  // there yet is taken as one of the robot's current session (it waits for
  // it). A candidate naming a robot without a keyframe yet (robots start
  // one after the other) waits for its first keyframe and returns -1; it is
  // added then, and refused then if degenerate (counted in
  // refused_waiting()). Throws DegenerateCandidate as
  // OnlineVerifier::AddLoop (keeping nothing), also when rrr.max_waiting
  // candidates wait for robots already, and std::out_of_range for a robot
  // that does not exist.
  int AddLoop(int robot_a, std::int64_t id_a, int robot_b, std::int64_t id_b,
              const Pose& z, const Information& information);
  // The id of robot `robot`'s keyframe nearest to `stamp_ns` (within
  // stamp_tolerance_ns) in the newest of its sessions that has one;
  // KeyframeStamps::kNotYet if the stamp is after the newest keyframe of its
  // current session (or it has none yet): a keyframe near it may still
  // come; else KeyframeStamps::kNone. Throws std::out_of_range for a robot
  // that does not exist.
  std::int64_t KeyframeAt(int robot, std::int64_t stamp_ns) const;
  // Adds the candidate z ≈ x_a⁻¹ · x_b between robot `robot_a`'s keyframe
  // at `stamp_a` and robot `robot_b`'s at `stamp_b` (ns, see KeyframeAt)
  // and returns its number, or -1 while a keyframe near a stamp may still
  // come: it waits, and is added (or refused, counted in refused_by_stamp())
  // with the keyframe that settles it. Throws DegenerateCandidate
  // (kUnknownPose) if a stamp has no keyframe near it, (kWaitingFull) if
  // rrr.max_waiting candidates wait by stamp already, and as AddLoop.
  int AddLoopByStamp(int robot_a, std::int64_t stamp_a, int robot_b,
                     std::int64_t stamp_b, const Pose& z,
                     const Information& information);
  int num_waiting_by_stamp() const { return waiting_by_stamp_.size(); }
  // Candidates that waited by stamp and were refused once their keyframes
  // settled (no keyframe near a stamp, or degenerate).
  int refused_by_stamp() const { return refused_by_stamp_; }
  // Candidates waiting for a robot's first keyframe.
  int num_waiting_for_robots() const {
    return static_cast<int>(waiting_for_robots_.size());
  }
  // Candidates that waited for a robot and were refused once it came.
  int refused_waiting() const { return refused_waiting_; }

  std::vector<DecisionChange> Update();
  std::vector<DecisionChange> Finish();

  // The verifier of every robot's chains; its candidate numbers are the
  // fleet's.
  const MapVerifier<Pose>& verifier() const { return verifier_; }
  // The candidate's ends as given to AddLoop (its sessions found).
  ChainPose from(int candidate) const { return ends_.at(candidate).first; }
  ChainPose to(int candidate) const { return ends_.at(candidate).second; }
  // The id (in its robot) of the keyframe as of which the candidate was
  // decided, or -1 while it is not.
  PoseId DecidedAt(int candidate) const;
  // The map chain `chain` is in: the lowest chain joined with it (itself if
  // none).
  int MapOfChain(int chain) const { return verifier_.MapOfChain(chain); }
  int num_chains() const { return verifier_.num_chains(); }
  // The keyframes of chain `chain`.
  int ChainSize(int chain) const {
    return static_cast<int>(verifier_.chains().poses(chain).size());
  }
  // Every chain in order (ids counted on over the chains, a gap of one id
  // between two), their odometry and every loop that has both poses, in the
  // order they entered the verifier's graph; `candidate_of_loop`, if given,
  // receives each loop's candidate number.
  PoseGraph<Pose> Graph(std::vector<int>* candidate_of_loop = nullptr) const;
  // The robot and session of chain `chain`.
  int robot_of_chain(int chain) const { return robot_of_chain_.at(chain); }
  // The robot's sessions (chains), oldest first.
  const std::vector<int>& sessions(int robot) const {
    return sessions_.at(robot);
  }
  // The map the robot's current session is in (its lowest chain; see
  // MapOfChain), or -1 before its first reading.
  int MapOfRobot(int robot) const;
  // The transform from the robot's odometry frame to its map's frame (the
  // correction of its newest keyframe), as of the last Update(); nothing
  // before its first keyframe.
  std::optional<Pose> MapToOdom(int robot) const;
  // The corrected poses of the robot's keyframes of the sessions in map
  // `map`, oldest first, as of the last Update() (keyframes added since
  // follow their odometry).
  std::vector<Pose> Path(int robot, int map) const;
  // The stamps of Path(robot, map)'s keyframes.
  std::vector<std::int64_t> PathStamps(int robot, int map) const;
  // The accepted graph of map `map` (a chain index, as MapOfRobot()), as of
  // the last Update(); empty for a chain that is not a map.
  FleetGraph<Pose> AcceptedGraph(int map) const;
  // The corrected pose of keyframe `pose` in its map's frame, as Path();
  // nothing if it does not exist.
  std::optional<Pose> Corrected(const ChainPose& pose) const;

 private:
  struct Session {
    int chain;
    std::int64_t first_id;
    PoseId base;  // the verifier's id of keyframe id k is base + k
    KeyframeTrack<Pose> track;  // its keyframes as odometry reported them
    std::vector<Pose> map;      // their corrected poses, in their map's frame
  };
  // Adds the candidates that waited for robots that have keyframes now.
  void AddWaitingLoops();
  // Refreshes every session's corrected poses from the verifier's maps.
  void RefreshMaps();
  // The session of robot `robot` holding keyframe `id` (the current one for
  // an id past its newest).
  const Session& SessionHolding(int robot, std::int64_t id) const;

  std::vector<std::string> robots_;
  FleetOptions options_;
  OdometryNoiseModel<Pose> noise_;
  MapVerifier<Pose> verifier_;
  std::vector<std::pair<ChainPose, ChainPose>> ends_;  // by candidate
  std::vector<Session> sessions_by_chain_;
  std::vector<int> robot_of_chain_;
  std::vector<std::vector<int>> sessions_;  // chains, by robot
  std::vector<std::int64_t> next_id_;       // by robot
  std::vector<bool> restart_;               // by robot
  std::vector<std::optional<KeyframeRecord<Pose>>> last_reading_;  // by robot
  struct WaitingLoop {
    int robot_a;
    std::int64_t id_a;
    int robot_b;
    std::int64_t id_b;
    Pose z;
    Information information;
  };
  std::vector<WaitingLoop> waiting_for_robots_;  // in arrival order
  int refused_waiting_ = 0;
  struct ByStamp {
    int robot_a, robot_b;
    Pose z;
    Information information;
  };
  // Adds the candidates named by stamp whose keyframes are settled.
  void AddSettledByStamp();
  StampedCandidates<ByStamp> waiting_by_stamp_;
  int refused_by_stamp_ = 0;
};

}  // namespace rrr

#endif  // RRR_FLEET_FLEET_H_
