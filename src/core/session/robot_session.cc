#include "rrr/session/robot_session.h"

#include <stdexcept>
#include <utility>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/rrr/map/map_verifier.h"
#include "rrr/rrr/published/incremental_verifier.h"

namespace rrr {
namespace {

// A driver started again reports its first pose at zero, or, by its first
// message, within this of it (m, and rad).
constexpr double kNearOrigin = 0.01;

template <class Pose>
bool NearOrigin(const Pose& pose) {
  return pose.translation().norm() <= kNearOrigin &&
         pose.angle() <= kNearOrigin;
}

template <class Pose>
std::unique_ptr<OnlineVerifier<Pose>> MakeVerifier(const RrrOptions& options) {
  if (options.procedure == Procedure::kMap) {
    return std::make_unique<MapVerifier<Pose>>(options);
  }
  return std::make_unique<IncrementalVerifier<Pose>>(options);
}

}  // namespace

template <class Pose>
RobotSession<Pose>::RobotSession(const RobotSessionOptions& options,
                                 OnSkip on_skip)
    : options_(options),
      on_skip_(std::move(on_skip)),
      verifier_(MakeVerifier<Pose>(options.rrr)),
      odometry_noise_(NoiseModelOf<Pose>(options.odometry)),
      keyframes_(TrackOf<Pose>(options.odometry)),
      stamped_waiting_(options.rrr.max_waiting) {}

template <class Pose>
RobotSession<Pose>::~RobotSession() = default;

template <class Pose>
ResumeSummary RobotSession<Pose>::Resume() {
  if (options_.database.empty()) return {};
  store_ = std::make_unique<SessionStore<Pose>>(
      options_.database, ToString(options_.rrr.procedure),
      options_.checkpoint_keyframes);
  const ResumeSummary summary = store_->Resume(
      verifier_.get(),
      [this](PoseId, const KeyframeRecord<Pose>& keyframe) {
        keyframes_.Append(keyframe);
      },
      [this](const StampedWaiting<Pose>& waiting) {
        if (!stamped_waiting_.Hold(waiting.from_ns, waiting.to_ns, waiting)) {
          store_->RecordStampedResolved(waiting.key);
          Skip(waiting.message, CandidateDefect::kWaitingFull,
               "the session holds more candidates waiting by stamp than "
               "max_waiting");
        }
      });
  if (summary.keyframes > 0) {
    resumed_ = true;
    resumed_until_ns_ = keyframes_.stamps().newest();
    MapChanged();
  }
  return summary;
}

template <class Pose>
typename RobotSession<Pose>::Taken RobotSession<Pose>::AddReading(
    const KeyframeRecord<Pose>& reading) {
  Taken taken;
  if (resumed_ && reading.stamp_ns <= resumed_until_ns_) {
    taken.already_recorded = true;
    return taken;
  }
  const auto judged = keyframes_.Judge(reading);
  if (!judged.problem.empty()) {
    taken.problem = judged.problem;
    return taken;
  }
  if (!judged.keyframe) return taken;
  if (keyframes_.empty()) {
    verifier_->AddFirstPose(0, reading.odometry_pose);
    if (store_) store_->RecordFirstKeyframe(0, reading);
  } else {
    using Source = typename OdometryNoiseModel<Pose>::Source;
    Source source;
    const KeyframeRecord<Pose> newest = keyframes_.newest();
    const Information information = odometry_noise_.EdgeInformation(
        newest.odometry_pose, newest.covariance, reading.odometry_pose,
        reading.covariance, options_.odometry.use_odometry_covariance, &source);
    taken.information_from_covariance = source == Source::kCovarianceChange;
    taken.restarted =
        options_.restart_jump > 0.0 && NearOrigin(reading.odometry_pose) &&
        newest.odometry_pose.translation().norm() > options_.restart_jump;
    if (taken.restarted) taken.jump = judged.motion.translation().norm();
    const PoseId id = verifier_->AddOdometry(judged.motion, information);
    if (store_) store_->RecordKeyframe(id, reading, judged.motion, information);
  }
  keyframes_.Append(reading);
  taken.keyframe = true;
  taken.id = verifier_->graph().ids().back();
  ResolveStampedLoops();
  return taken;
}

template <class Pose>
void RobotSession<Pose>::AddCandidate(std::int64_t message, PoseId from,
                                      PoseId to, const Pose& z,
                                      const Information& information) {
  if (from < 0 || to < 0) {
    return Skip(message, CandidateDefect::kUnknownPose,
                "keyframe ids start at 0");
  }
  try {
    const int number = verifier_->AddLoop(from, to, z, information);
    if (store_) store_->RecordCandidate(number, from, to, z, information);
  } catch (const DegenerateCandidate& e) {
    Skip(message, e.defect(), e.what());
  }
}

template <class Pose>
void RobotSession<Pose>::AddCandidateByStamp(std::int64_t message,
                                             std::int64_t from_ns,
                                             std::int64_t to_ns, const Pose& z,
                                             const Information& information) {
  if (stamped_waiting_.full()) {
    return Skip(message, CandidateDefect::kWaitingFull,
                std::to_string(stamped_waiting_.size()) +
                    " candidates wait for keyframes by stamp already");
  }
  StampedWaiting<Pose> waiting{0, message, from_ns, to_ns, z, information};
  if (store_) {
    waiting.key =
        store_->RecordStampedWaiting(message, from_ns, to_ns, z, information);
  }
  stamped_waiting_.Hold(from_ns, to_ns, waiting);
  ResolveStampedLoops();
}

template <class Pose>
void RobotSession<Pose>::ResolveStampedLoops() {
  stamped_waiting_.Resolve(
      keyframes_.stamps(),
      [this](int from, int to, const StampedWaiting<Pose>& loop) {
        if (store_) store_->RecordStampedResolved(loop.key);
        AddCandidate(loop.message, verifier_->graph().ids()[from],
                     verifier_->graph().ids()[to], loop.measurement,
                     loop.information);
      },
      [this](const char* end, const StampedWaiting<Pose>& loop) {
        if (store_) store_->RecordStampedResolved(loop.key);
        Skip(loop.message, CandidateDefect::kUnknownPose,
             "no keyframe within " +
                 std::to_string(options_.odometry.stamp_tolerance_ns * 1e-9) +
                 " s of its " + end + " stamp");
      });
}

template <class Pose>
typename RobotSession<Pose>::Updated RobotSession<Pose>::Update(bool finish) {
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
  if (updated.accepted_changed || finish) MapChanged();
  return updated;
}

template <class Pose>
void RobotSession<Pose>::MapChanged() {
  const int poses = verifier_->graph().num_poses();
  if (poses == 0) return;
  const std::vector<Pose> ends = verifier_->MapAt({0, poses - 1});
  keyframes_.SetNewest(ends[0], ends[1]);
  map_stale_ = true;
}

template <class Pose>
const std::vector<Pose>& RobotSession<Pose>::Map() {
  if (map_stale_) {
    keyframes_.SetMap(verifier_->Map());
    map_stale_ = false;
  }
  return keyframes_.map();
}

template <class Pose>
void RobotSession<Pose>::Skip(std::int64_t message, CandidateDefect defect,
                              const std::string& why) {
  if (on_skip_) on_skip_({message, defect, why});
}

template class RobotSession<Pose2>;
template class RobotSession<Pose3>;

}  // namespace rrr
