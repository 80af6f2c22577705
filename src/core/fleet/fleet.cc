#include "rrr/fleet/fleet.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/graph/candidate_defect.h"
#include "rrr/graph/chain_spans.h"

namespace rrr {
template <class Pose>
Fleet<Pose>::Fleet(std::vector<std::string> robots, const FleetOptions& options)
    : robots_(std::move(robots)),
      options_(options),
      noise_(NoiseModelOf<Pose>(options.odometry)),
      verifier_(options.rrr),
      sessions_(robots_.size()),
      next_id_(robots_.size(), 0),
      restart_(robots_.size(), false),
      last_reading_(robots_.size()),
      waiting_by_stamp_(options.rrr.max_waiting) {
  if (robots_.empty()) throw std::invalid_argument("a fleet needs a robot");
  for (size_t r = 0; r < robots_.size(); ++r) {
    if (robots_[r].empty()) {
      throw std::invalid_argument("robot " + std::to_string(r) +
                                  " has an empty name");
    }
    if (std::count(robots_.begin(), robots_.end(), robots_[r]) > 1) {
      throw std::invalid_argument("robot '" + robots_[r] + "' is named twice");
    }
  }
  if (options.restart_jump < 0.0) {
    throw std::invalid_argument("restart_jump must not be negative");
  }
}

template <class Pose>
int Fleet<Pose>::RobotIndex(const std::string& name) const {
  const auto it = std::find(robots_.begin(), robots_.end(), name);
  return it == robots_.end() ? -1 : static_cast<int>(it - robots_.begin());
}

template <class Pose>
void Fleet<Pose>::StartSession(int robot) {
  restart_.at(robot) = true;
}

template <class Pose>
typename Fleet<Pose>::Taken Fleet<Pose>::AddReading(
    int robot, const KeyframeRecord<Pose>& reading) {
  const std::optional<KeyframeRecord<Pose>>& last = last_reading_.at(robot);
  const bool restarts =
      !last || restart_[robot] || reading.stamp_ns < last->stamp_ns ||
      (options_.restart_jump > 0.0 &&
       (last->odometry_pose.between(reading.odometry_pose).translation())
               .norm() > options_.restart_jump);
  if (restarts) return AddKeyframe(robot, reading, true);
  Taken taken;
  const auto judged =
      sessions_by_chain_[sessions_[robot].back()].track.Judge(reading);
  if (!judged.problem.empty()) {
    taken.problem = judged.problem;
    return taken;
  }
  if (!judged.keyframe) {
    last_reading_[robot] = reading;
    return taken;
  }
  return AddKeyframe(robot, reading, false);
}

template <class Pose>
typename Fleet<Pose>::Taken Fleet<Pose>::AddKeyframe(
    int robot, const KeyframeRecord<Pose>& keyframe, bool new_session) {
  if (!new_session && sessions_.at(robot).empty()) {
    throw std::logic_error("robot '" + robots_[robot] +
                           "' has no session to continue");
  }
  Taken taken;
  taken.keyframe = true;
  taken.new_session = new_session;
  taken.id = next_id_[robot]++;
  last_reading_[robot] = keyframe;
  if (new_session) {
    // The verifier's ids: each robot's apart, a gap of one between sessions.
    const PoseId base = (static_cast<PoseId>(robot) << 40) +
                        static_cast<PoseId>(sessions_[robot].size());
    taken.chain = verifier_.AddChain(base + taken.id, keyframe.odometry_pose);
    sessions_by_chain_.push_back({taken.chain,
                                  taken.id,
                                  base,
                                  TrackOf<Pose>(options_.odometry),
                                  {keyframe.odometry_pose}});
    sessions_by_chain_.back().track.Append(keyframe);
    robot_of_chain_.push_back(robot);
    sessions_[robot].push_back(taken.chain);
    restart_[robot] = false;
    if (sessions_[robot].size() == 1) AddWaitingLoops();
    AddSettledByStamp();
    return taken;
  }
  Session& session = sessions_by_chain_[sessions_[robot].back()];
  const KeyframeRecord<Pose> newest = session.track.newest();
  const Pose motion = newest.odometry_pose.between(keyframe.odometry_pose);
  const Information information = noise_.EdgeInformation(
      newest.odometry_pose, newest.covariance, keyframe.odometry_pose,
      keyframe.covariance, options_.odometry.use_odometry_covariance);
  verifier_.AddOdometry(session.chain, motion, information);
  session.track.Append(keyframe);
  session.map.push_back(session.map.back() * motion);
  taken.chain = session.chain;
  AddSettledByStamp();
  return taken;
}

template <class Pose>
std::int64_t Fleet<Pose>::KeyframeAt(int robot, std::int64_t stamp_ns) const {
  const std::vector<int>& chains = sessions_.at(robot);
  if (chains.empty()) return KeyframeStamps::kNotYet;
  for (auto c = chains.rbegin(); c != chains.rend(); ++c) {
    const Session& session = sessions_by_chain_[*c];
    const int k = session.track.stamps().Find(stamp_ns);
    if (k >= 0) return session.first_id + k;
    if (k == KeyframeStamps::kNotYet && c == chains.rbegin()) return k;
  }
  return KeyframeStamps::kNone;
}

template <class Pose>
int Fleet<Pose>::AddLoopByStamp(int robot_a, std::int64_t stamp_a, int robot_b,
                                std::int64_t stamp_b, const Pose& z,
                                const Information& information) {
  const std::int64_t a = KeyframeAt(robot_a, stamp_a);
  const std::int64_t b = KeyframeAt(robot_b, stamp_b);
  if (a == KeyframeStamps::kNotYet || b == KeyframeStamps::kNotYet) {
    if (waiting_by_stamp_.full()) {
      throw DegenerateCandidate(
          CandidateDefect::kWaitingFull,
          std::to_string(waiting_by_stamp_.size()) +
              " candidates wait for keyframes by stamp already");
    }
    waiting_by_stamp_.Hold(stamp_a, stamp_b,
                           {robot_a, robot_b, z, information});
    return -1;
  }
  if (a < 0 || b < 0) {
    const int robot = a < 0 ? robot_a : robot_b;
    throw DegenerateCandidate(
        CandidateDefect::kUnknownPose,
        "robot '" + robots_[robot] + "' has no keyframe within " +
            std::to_string(options_.odometry.stamp_tolerance_ns * 1e-9) +
            " s of the " + (a < 0 ? "from" : "to") + " stamp");
  }
  return AddLoop(robot_a, a, robot_b, b, z, information);
}

template <class Pose>
void Fleet<Pose>::AddSettledByStamp() {
  if (waiting_by_stamp_.size() == 0) return;
  waiting_by_stamp_.ResolveWith(
      [this](std::int64_t stamp_ns, const char* end, const ByStamp& w) {
        return KeyframeAt(end[0] == 'f' ? w.robot_a : w.robot_b, stamp_ns);
      },
      [this](std::int64_t a, std::int64_t b, const ByStamp& w) {
        try {
          AddLoop(w.robot_a, a, w.robot_b, b, w.z, w.information);
        } catch (const DegenerateCandidate&) {
          ++refused_by_stamp_;
        }
      },
      [this](const char*, const ByStamp&) { ++refused_by_stamp_; });
}

template <class Pose>
const typename Fleet<Pose>::Session& Fleet<Pose>::SessionHolding(
    int robot, std::int64_t id) const {
  const std::vector<int>& chains = sessions_.at(robot);
  if (chains.empty()) {
    throw std::out_of_range("robot '" + robots_[robot] +
                            "' has no keyframe yet");
  }
  for (auto c = chains.rbegin(); c != chains.rend(); ++c) {
    if (sessions_by_chain_[*c].first_id <= id) return sessions_by_chain_[*c];
  }
  return sessions_by_chain_[chains.front()];  // before its first: refused
}

template <class Pose>
int Fleet<Pose>::AddLoop(int robot_a, std::int64_t id_a, int robot_b,
                         std::int64_t id_b, const Pose& z,
                         const Information& information) {
  if (sessions_.at(robot_a).empty() || sessions_.at(robot_b).empty()) {
    if (static_cast<int>(waiting_for_robots_.size()) >=
        options_.rrr.max_waiting) {
      throw DegenerateCandidate(
          CandidateDefect::kWaitingFull,
          "a candidate would wait for a robot's first keyframe while " +
              std::to_string(options_.rrr.max_waiting) + " wait already");
    }
    waiting_for_robots_.push_back(
        {robot_a, id_a, robot_b, id_b, z, information});
    return -1;
  }
  const Session& a = SessionHolding(robot_a, id_a);
  const Session& b = SessionHolding(robot_b, id_b);
  const int candidate =
      verifier_.AddLoop(a.base + id_a, b.base + id_b, z, information);
  ends_.push_back({{a.chain, id_a}, {b.chain, id_b}});
  return candidate;
}

template <class Pose>
void Fleet<Pose>::AddWaitingLoops() {
  std::vector<WaitingLoop> still;
  for (const WaitingLoop& w : waiting_for_robots_) {
    if (sessions_[w.robot_a].empty() || sessions_[w.robot_b].empty()) {
      still.push_back(w);
      continue;
    }
    try {
      AddLoop(w.robot_a, w.id_a, w.robot_b, w.id_b, w.z, w.information);
    } catch (const DegenerateCandidate&) {
      ++refused_waiting_;
    }
  }
  waiting_for_robots_ = std::move(still);
}

template <class Pose>
std::vector<DecisionChange> Fleet<Pose>::Update() {
  std::vector<DecisionChange> changes = verifier_.Update();
  RefreshMaps();
  return changes;
}

template <class Pose>
std::vector<DecisionChange> Fleet<Pose>::Finish() {
  std::vector<DecisionChange> changes = verifier_.Finish();
  RefreshMaps();
  return changes;
}

template <class Pose>
void Fleet<Pose>::RefreshMaps() {
  const std::vector<Pose> map = verifier_.Map();
  for (Session& session : sessions_by_chain_) {
    const std::vector<int>& poses = verifier_.chains().poses(session.chain);
    session.map.resize(poses.size());
    for (size_t k = 0; k < poses.size(); ++k) session.map[k] = map[poses[k]];
  }
}

template <class Pose>
PoseId Fleet<Pose>::DecidedAt(int candidate) const {
  const int pose = verifier_.reason(candidate).pose;
  if (pose < 0) return -1;
  const ChainOdometry<Pose>& chains = verifier_.chains();
  return sessions_by_chain_[chains.chain_of(pose)].first_id +
         chains.position(pose);
}

template <class Pose>
PoseGraph<Pose> Fleet<Pose>::Graph(std::vector<int>* candidate_of_loop) const {
  const PoseGraph<Pose>& all = verifier_.graph();
  const ChainOdometry<Pose>& chains = verifier_.chains();
  PoseGraph<Pose> graph;
  std::vector<int> index(all.num_poses());
  PoseId id = 0;
  for (int c = 0; c < chains.num_chains(); ++c) {
    for (const int p : chains.poses(c)) {
      index[p] = graph.AddPose(id++, all.estimates()[p]);
    }
    ++id;
  }
  for (Constraint<Pose> e : all.odometry()) {
    e.from = index[e.from];
    e.to = index[e.to];
    graph.AddEdge(e);
  }
  std::vector<int> candidate(all.loops().size(), -1);
  for (int c = 0; c < verifier_.num_candidates(); ++c) {
    if (verifier_.loop_of(c) >= 0) candidate[verifier_.loop_of(c)] = c;
  }
  for (Constraint<Pose> e : all.loops()) {
    e.from = index[e.from];
    e.to = index[e.to];
    graph.AddEdge(e);
  }
  if (candidate_of_loop) *candidate_of_loop = std::move(candidate);
  return graph;
}

template <class Pose>
int Fleet<Pose>::MapOfRobot(int robot) const {
  const std::vector<int>& chains = sessions_.at(robot);
  return chains.empty() ? -1 : verifier_.MapOfChain(chains.back());
}

template <class Pose>
std::optional<Pose> Fleet<Pose>::MapToOdom(int robot) const {
  const std::vector<int>& chains = sessions_.at(robot);
  if (chains.empty()) return std::nullopt;
  const Session& session = sessions_by_chain_[chains.back()];
  return session.map.back() * session.track.newest().odometry_pose.inverse();
}

template <class Pose>
std::vector<Pose> Fleet<Pose>::Path(int robot, int map) const {
  std::vector<Pose> path;
  for (const int chain : sessions_.at(robot)) {
    if (verifier_.MapOfChain(chain) != map) continue;
    const std::vector<Pose>& poses = sessions_by_chain_[chain].map;
    path.insert(path.end(), poses.begin(), poses.end());
  }
  return path;
}

template <class Pose>
std::vector<std::int64_t> Fleet<Pose>::PathStamps(int robot, int map) const {
  std::vector<std::int64_t> stamps;
  for (const int chain : sessions_.at(robot)) {
    if (verifier_.MapOfChain(chain) != map) continue;
    const auto& own = sessions_by_chain_[chain].track.stamps().stamps();
    stamps.insert(stamps.end(), own.begin(), own.end());
  }
  return stamps;
}

template <class Pose>
FleetGraph<Pose> Fleet<Pose>::AcceptedGraph(int map) const {
  std::vector<int> candidate_of_loop;
  const PoseGraph<Pose> all = Graph(&candidate_of_loop);
  FleetGraph<Pose> out;
  std::vector<ChainSpan> spans;
  std::vector<Pose> estimates = all.estimates();
  int offset = 0;
  for (int c = 0; c < num_chains(); ++c) {
    const int poses = ChainSize(c);
    if (verifier_.MapOfChain(c) == map) {
      const Session& session = sessions_by_chain_[c];
      spans.push_back({offset, offset + poses - 1});
      for (int k = 0; k < poses; ++k) {
        estimates[offset + k] = session.map[k];
        out.robot.push_back(robot_of_chain_[c]);
        out.keyframe.push_back(session.first_id + k);
      }
    }
    offset += poses;
  }
  const auto in_map = [&](int pose) {
    return std::any_of(spans.begin(), spans.end(),
                       [&](const ChainSpan& s) { return s.Holds(pose); });
  };
  std::vector<int> loops;
  for (size_t k = 0; k < all.loops().size(); ++k) {
    const auto& e = all.loops()[k];
    if (verifier_.state(candidate_of_loop[k]) == LoopState::kAccepted &&
        in_map(e.from) && in_map(e.to)) {
      loops.push_back(static_cast<int>(k));
    }
  }
  out.graph = SubGraph(all, spans, estimates, loops);
  return out;
}

template <class Pose>
std::optional<Pose> Fleet<Pose>::Corrected(const ChainPose& pose) const {
  const Session& session = sessions_by_chain_.at(pose.chain);
  const std::int64_t k = pose.id - session.first_id;
  if (k < 0 || k >= static_cast<std::int64_t>(session.map.size())) {
    return std::nullopt;
  }
  return session.map[k];
}

template class Fleet<Pose2>;
template class Fleet<Pose3>;

}  // namespace rrr
