#include "rrr/session/session.h"

#include <algorithm>
#include <filesystem>
#include <stdexcept>
#include <utility>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/graph/chain_spans.h"
#include "rrr/rrr/map/map_verifier.h"
#include "rrr/rrr/published/incremental_verifier.h"

namespace rrr {
namespace {

// A driver started again reports its first pose at zero, or, by its first
// message, within this of it (m, and rad).
constexpr double kNearOrigin = 0.01;

template <class Pose>
std::unique_ptr<OnlineVerifier<Pose>> MakeVerifier(const RrrOptions& options) {
  if (options.procedure == Procedure::kMap) {
    return std::make_unique<MapVerifier<Pose>>(options);
  }
  return std::make_unique<IncrementalVerifier<Pose>>(options);
}

}  // namespace

template <class Pose>
Session<Pose>::Session(std::vector<std::string> robots,
                       const SessionOptions& options, OnSkip on_skip)
    : robots_(std::move(robots)),
      options_(options),
      on_skip_(std::move(on_skip)),
      verifier_(MakeVerifier<Pose>(options.rrr)),
      noise_(NoiseModelOf<Pose>(options.odometry)),
      sessions_(robots_.size()),
      next_id_(robots_.size(), 0),
      last_reading_(robots_.size()),
      resumed_until_ns_(robots_.size(), -1),
      by_stamp_(options.rrr.max_waiting) {
  TrackOf<Pose>(options.odometry);  // validates the keyframe options
  if (const std::string bad = RobotNamesProblem(robots_); !bad.empty()) {
    throw std::invalid_argument(bad);
  }
  if (robots_.size() > 1 && !verifier_->JudgesSeveralChains()) {
    throw std::invalid_argument(
        std::string("the ") + ToString(options.rrr.procedure) +
        " procedure judges one robot's one odometry chain, not a fleet");
  }
  if (options.restart_jump < 0.0) {
    throw std::invalid_argument("restart_jump must not be negative");
  }
}

template <class Pose>
Session<Pose>::~Session() = default;

template <class Pose>
ResumeSummary Session<Pose>::Resume() {
  if (options_.database.empty()) return {};
  store_ = std::make_unique<SessionStore<Pose>>(
      options_.database, robots_, options_.rrr, options_.checkpoint_keyframes);
  replaying_ = true;
  const ResumeSummary summary = store_->Resume(this, verifier_.get());
  replaying_ = false;
  for (size_t r = 0; r < robots_.size(); ++r) {
    if (last_reading_[r]) resumed_until_ns_[r] = last_reading_[r]->stamp_ns;
  }
  map_stale_ = true;
  return summary;
}

template <class Pose>
int Session<Pose>::RobotIndex(const std::string& name) const {
  const auto it = std::find(robots_.begin(), robots_.end(), name);
  return it == robots_.end() ? -1 : static_cast<int>(it - robots_.begin());
}

template <class Pose>
typename Session<Pose>::Taken Session<Pose>::AddReading(
    int robot, const KeyframeRecord<Pose>& reading) {
  RequireResumed();
  const std::optional<KeyframeRecord<Pose>>& last = last_reading_.at(robot);
  Taken taken;
  if (reading.stamp_ns <= resumed_until_ns_[robot]) {
    taken.already_recorded = true;
    return taken;
  }
  const bool restarts =
      last &&
      (reading.stamp_ns < last->stamp_ns ||
       (options_.restart_jump > 0.0 &&
        reading.odometry_pose.translation().norm() <= kNearOrigin &&
        reading.odometry_pose.angle() <= kNearOrigin &&
        last->odometry_pose.translation().norm() > options_.restart_jump));
  if (!last || (restarts && verifier_->JudgesSeveralChains())) {
    return AddKeyframe(robot, reading, true);
  }
  const auto judged = chains_[sessions_[robot].back()].track.Judge(reading);
  if (!judged.problem.empty()) {
    taken.problem = judged.problem;
    return taken;
  }
  if (!judged.keyframe) {
    last_reading_[robot] = reading;
    return taken;
  }
  taken = AddKeyframe(robot, reading, false);
  taken.restarted = restarts;
  if (restarts) taken.jump = judged.motion.translation().norm();
  return taken;
}

template <class Pose>
typename Session<Pose>::Taken Session<Pose>::AddKeyframe(
    int robot, const KeyframeRecord<Pose>& keyframe, bool new_session,
    const Information* information) {
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
    // The procedure's ids: each robot's apart, a gap of one between its
    // sessions.
    const PoseId base = (static_cast<PoseId>(robot) << 40) +
                        static_cast<PoseId>(sessions_[robot].size());
    taken.chain = verifier_->AddChain(base + taken.id, keyframe.odometry_pose);
    chains_.push_back(
        {robot, taken.id, base, TrackOf<Pose>(options_.odometry)});
    chains_.back().track.Append(keyframe);
    sessions_[robot].push_back(taken.chain);
  } else {
    Chain& chain = chains_[sessions_[robot].back()];
    const KeyframeRecord<Pose> newest = chain.track.newest();
    using Source = typename OdometryNoiseModel<Pose>::Source;
    Source source = Source::kCovarianceChange;
    taken.information =
        information ? *information
                    : noise_.EdgeInformation(
                          newest.odometry_pose, newest.covariance,
                          keyframe.odometry_pose, keyframe.covariance,
                          options_.odometry.use_odometry_covariance, &source);
    taken.information_from_covariance = source == Source::kCovarianceChange;
    verifier_->AddOdometry(sessions_[robot].back(),
                           newest.odometry_pose.between(keyframe.odometry_pose),
                           taken.information);
    chain.track.Append(keyframe);
    taken.chain = sessions_[robot].back();
  }
  map_stale_ = true;
  if (Recording()) store_->RecordKeyframe(robot, keyframe, taken);
  AddWaiting();
  return taken;
}

template <class Pose>
const typename Session<Pose>::Chain& Session<Pose>::ChainHolding(
    int robot, PoseId id) const {
  const std::vector<int>& chains = sessions_.at(robot);
  for (auto c = chains.rbegin(); c != chains.rend(); ++c) {
    if (chains_[*c].first_id <= id) return chains_[*c];
  }
  return chains_[chains.front()];  // before its first: refused
}

template <class Pose>
void Session<Pose>::AddCandidate(std::int64_t message, int robot_a, PoseId id_a,
                                 int robot_b, PoseId id_b, const Pose& z,
                                 const Information& information) {
  RequireResumed();
  if (sessions_.at(robot_a).empty() || sessions_.at(robot_b).empty()) {
    if (static_cast<int>(for_robots_.size()) >= options_.rrr.max_waiting) {
      return Skip(message, CandidateDefect::kWaitingFull,
                  "it would wait for a robot's first keyframe while " +
                      std::to_string(options_.rrr.max_waiting) +
                      " candidates wait already");
    }
    for_robots_.push_back(
        {message, robot_a, robot_b, id_a, id_b, z, information});
    if (Recording()) {
      store_->RecordCandidate(message, robot_a, id_a, robot_b, id_b, z,
                              information, false);
    }
    return;
  }
  if (id_a < 0 || id_b < 0) {
    return Skip(message, CandidateDefect::kUnknownPose,
                "keyframe ids start at 0");
  }
  const Chain& a = ChainHolding(robot_a, id_a);
  const Chain& b = ChainHolding(robot_b, id_b);
  try {
    verifier_->AddLoop(a.base + id_a, b.base + id_b, z, information);
  } catch (const DegenerateCandidate& e) {
    return Skip(message, e.defect(), e.what());
  }
  const int chain_a = static_cast<int>(&a - chains_.data());
  const int chain_b = static_cast<int>(&b - chains_.data());
  ends_.push_back({{chain_a, id_a}, {chain_b, id_b}});
  if (Recording()) {
    store_->RecordCandidate(message, robot_a, id_a, robot_b, id_b, z,
                            information, false);
  }
}

template <class Pose>
void Session<Pose>::AddCandidateByStamp(std::int64_t message, int robot_a,
                                        std::int64_t stamp_a, int robot_b,
                                        std::int64_t stamp_b, const Pose& z,
                                        const Information& information) {
  RequireResumed();
  sessions_.at(robot_a);
  sessions_.at(robot_b);
  if (by_stamp_.full()) {
    return Skip(message, CandidateDefect::kWaitingFull,
                std::to_string(by_stamp_.size()) +
                    " candidates wait for keyframes by stamp already");
  }
  if (Recording()) {
    store_->RecordCandidate(message, robot_a, stamp_a, robot_b, stamp_b, z,
                            information, true);
  }
  by_stamp_.Hold(stamp_a, stamp_b,
                 {message, robot_a, robot_b, stamp_a, stamp_b, z, information});
  AddWaiting();
}

template <class Pose>
void Session<Pose>::AddWaiting() {
  // The candidates added from here are recorded already.
  resolving_ = true;
  if (!for_robots_.empty()) {
    std::vector<Waiting> still;
    for (const Waiting& w : for_robots_) {
      if (sessions_[w.robot_a].empty() || sessions_[w.robot_b].empty()) {
        still.push_back(w);
      } else {
        AddCandidate(w.message, w.robot_a, w.a, w.robot_b, w.b, w.z,
                     w.information);
      }
    }
    for_robots_ = std::move(still);
  }
  if (by_stamp_.size() > 0) {
    // The keyframe of a robot nearest the stamp, in the newest of its
    // sessions that has one; kNotYet while one may still come.
    const auto keyframe_at = [this](int robot, std::int64_t stamp_ns) {
      const std::vector<int>& chains = sessions_[robot];
      if (chains.empty()) return std::int64_t{KeyframeStamps::kNotYet};
      for (auto c = chains.rbegin(); c != chains.rend(); ++c) {
        const int k = chains_[*c].track.stamps().Find(stamp_ns);
        if (k >= 0) return chains_[*c].first_id + k;
        if (k == KeyframeStamps::kNotYet && c == chains.rbegin()) {
          return std::int64_t{k};
        }
      }
      return std::int64_t{KeyframeStamps::kNone};
    };
    by_stamp_.ResolveWith(
        [&](std::int64_t stamp_ns, const char* end, const Waiting& w) {
          return keyframe_at(end[0] == 'f' ? w.robot_a : w.robot_b, stamp_ns);
        },
        [&](std::int64_t a, std::int64_t b, const Waiting& w) {
          AddCandidate(w.message, w.robot_a, a, w.robot_b, b, w.z,
                       w.information);
        },
        [&](const char* end, const Waiting& w) {
          Skip(w.message, CandidateDefect::kUnknownPose,
               std::string("no keyframe within ") +
                   std::to_string(options_.odometry.stamp_tolerance_ns * 1e-9) +
                   " s of its " + end + " stamp");
        });
  }
  resolving_ = false;
}

template <class Pose>
typename Session<Pose>::Updated Session<Pose>::Update(bool finish) {
  RequireResumed();
  Updated updated;
  updated.changes = finish ? verifier_->Finish() : verifier_->Update();
  if (store_) {
    try {
      store_->CommitUpdate(finish, updated.changes, verifier_.get());
    } catch (const SessionError& e) {
      updated.store_error = e.what();
    }
  }
  for (const DecisionChange& change : updated.changes) {
    updated.accepted_changed = updated.accepted_changed ||
                               change.previous == LoopState::kAccepted ||
                               change.current == LoopState::kAccepted;
  }
  map_stale_ = true;
  return updated;
}

template <class Pose>
void Session<Pose>::RequireResumed() const {
  if (!options_.database.empty() && !store_) {
    throw std::logic_error(
        "a session with a database takes no input before "
        "Resume()");
  }
}

template <class Pose>
void Session<Pose>::Skip(std::int64_t message, CandidateDefect defect,
                         const std::string& why) {
  if (on_skip_ && !replaying_) on_skip_({message, defect, why});
}

template <class Pose>
PoseId Session<Pose>::DecidedAt(int candidate) const {
  const int pose = verifier_->reason(candidate).pose;
  if (pose < 0) return -1;
  const ChainOdometry<Pose>& chains = verifier_->chains();
  return chains_[chains.chain_of(pose)].first_id + chains.position(pose);
}

template <class Pose>
int Session<Pose>::MapOfRobot(int robot) const {
  const std::vector<int>& chains = sessions_.at(robot);
  return chains.empty() ? -1 : MapOfChain(chains.back());
}

template <class Pose>
std::optional<Pose> Session<Pose>::MapToOdom(int robot) const {
  const std::vector<int>& chains = sessions_.at(robot);
  if (chains.empty()) return std::nullopt;
  const int newest = verifier_->chains().poses(chains.back()).back();
  return verifier_->MapAt({newest}).front() *
         chains_[chains.back()].track.newest().odometry_pose.inverse();
}

template <class Pose>
void Session<Pose>::RefreshMap() {
  if (!map_stale_) return;
  map_ = verifier_->Map();
  map_stale_ = false;
}

template <class Pose>
std::vector<Pose> Session<Pose>::Path(int robot, int map) {
  RefreshMap();
  std::vector<Pose> path;
  for (const int chain : sessions_.at(robot)) {
    if (MapOfChain(chain) != map) continue;
    for (const int p : verifier_->chains().poses(chain)) {
      path.push_back(map_[p]);
    }
  }
  return path;
}

template <class Pose>
std::vector<std::int64_t> Session<Pose>::PathStamps(int robot, int map) const {
  std::vector<std::int64_t> stamps;
  for (const int chain : sessions_.at(robot)) {
    if (MapOfChain(chain) != map) continue;
    const auto& own = chains_[chain].track.stamps().stamps();
    stamps.insert(stamps.end(), own.begin(), own.end());
  }
  return stamps;
}

template <class Pose>
std::optional<Pose> Session<Pose>::Corrected(const ChainPose& pose) {
  const std::int64_t k = pose.id - chains_.at(pose.chain).first_id;
  const std::vector<int>& poses = verifier_->chains().poses(pose.chain);
  if (k < 0 || k >= static_cast<std::int64_t>(poses.size())) {
    return std::nullopt;
  }
  RefreshMap();
  return map_[poses[k]];
}

template <class Pose>
PoseGraph<Pose> Session<Pose>::Graph(std::vector<int>* candidate_of_loop,
                                     std::vector<int>* index_of_pose) {
  RefreshMap();
  const PoseGraph<Pose>& all = verifier_->graph();
  const ChainOdometry<Pose>& chains = verifier_->chains();
  PoseGraph<Pose> graph;
  std::vector<int> index(all.num_poses());
  PoseId id = 0;
  for (int c = 0; c < chains.num_chains(); ++c) {
    for (const int p : chains.poses(c)) index[p] = graph.AddPose(id++, map_[p]);
    ++id;
  }
  for (Constraint<Pose> e : all.odometry()) {
    e.from = index[e.from];
    e.to = index[e.to];
    graph.AddEdge(e);
  }
  for (Constraint<Pose> e : all.loops()) {
    e.from = index[e.from];
    e.to = index[e.to];
    graph.AddEdge(e);
  }
  if (index_of_pose) *index_of_pose = index;
  if (candidate_of_loop) {
    candidate_of_loop->assign(all.loops().size(), -1);
    for (int c = 0; c < verifier_->num_candidates(); ++c) {
      if (verifier_->loop_of(c) >= 0) {
        (*candidate_of_loop)[verifier_->loop_of(c)] = c;
      }
    }
  }
  return graph;
}

template <class Pose>
typename Session<Pose>::MapGraph Session<Pose>::AcceptedGraph(int map) {
  std::vector<int> candidate_of_loop;
  const PoseGraph<Pose> all = Graph(&candidate_of_loop);
  MapGraph out;
  std::vector<ChainSpan> spans;
  std::vector<bool> in_map(all.num_poses(), false);
  for (int c = 0, offset = 0; c < num_chains(); offset += ChainSize(c), ++c) {
    if (MapOfChain(c) != map) continue;
    spans.push_back({offset, offset + ChainSize(c) - 1});
    for (int k = 0; k < ChainSize(c); ++k) {
      in_map[offset + k] = true;
      out.robot.push_back(chains_[c].robot);
      out.keyframe.push_back(chains_[c].first_id + k);
    }
  }
  std::vector<int> loops;
  for (size_t k = 0; k < all.loops().size(); ++k) {
    const auto& e = all.loops()[k];
    if (verifier_->state(candidate_of_loop[k]) == LoopState::kAccepted &&
        in_map[e.from] && in_map[e.to]) {
      loops.push_back(static_cast<int>(k));
    }
  }
  out.graph = SubGraph(all, spans, all.estimates(), loops);
  return out;
}

template <class Pose>
std::unique_ptr<Session<Pose>> ReplaySession(const std::string& path,
                                             const std::string& copy,
                                             SessionOptions options) {
  const SessionDatabase recorded = ReadSessionDatabase(path);
  namespace fs = std::filesystem;
  for (const std::string part : {"", "-wal", "-shm"}) {
    std::error_code error;
    fs::remove(copy + part, error);
    if (part != "-shm" && fs::exists(path + part)) {
      fs::copy_file(path + part, copy + part, error);
      if (error) {
        throw SessionError(path, "cannot be copied: " + error.message());
      }
    }
  }
  options.database = copy;
  options.rrr.procedure = recorded.options.procedure;
  auto session =
      std::make_unique<Session<Pose>>(recorded.robots, options, nullptr);
  try {
    session->Resume();
  } catch (const SessionError& e) {
    throw SessionError(path, e.what());
  }
  return session;
}

template class Session<Pose2>;
template class Session<Pose3>;
template std::unique_ptr<Session<Pose2>> ReplaySession(const std::string&,
                                                       const std::string&,
                                                       SessionOptions);
template std::unique_ptr<Session<Pose3>> ReplaySession(const std::string&,
                                                       const std::string&,
                                                       SessionOptions);

}  // namespace rrr
