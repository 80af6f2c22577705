#include "rrr/session/fleet_session.h"

#include <utility>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"

namespace rrr {

template <class Pose>
FleetSession<Pose>::FleetSession(std::vector<std::string> robots,
                                 const FleetOptions& options,
                                 std::string database)
    : fleet_(std::move(robots), options),
      database_(std::move(database)),
      procedure_(ToString(options.rrr.procedure)) {}

template <class Pose>
FleetSession<Pose>::~FleetSession() = default;

template <class Pose>
FleetResumeSummary FleetSession<Pose>::Resume() {
  if (database_.empty()) return {};
  store_ = std::make_unique<FleetStore<Pose>>(database_, fleet_.robots(),
                                              procedure_);
  return store_->Resume(&fleet_);
}

template <class Pose>
typename Fleet<Pose>::Taken FleetSession<Pose>::AddReading(
    int robot, const KeyframeRecord<Pose>& reading) {
  const typename Fleet<Pose>::Taken taken = fleet_.AddReading(robot, reading);
  if (taken.keyframe && store_) store_->RecordKeyframe(robot, reading, taken);
  return taken;
}

template <class Pose>
int FleetSession<Pose>::AddLoop(int robot_a, std::int64_t id_a, int robot_b,
                                std::int64_t id_b, const Pose& z,
                                const Information& information) {
  const int number =
      fleet_.AddLoop(robot_a, id_a, robot_b, id_b, z, information);
  if (store_) {
    store_->RecordCandidate(number, robot_a, id_a, robot_b, id_b, z,
                            information);
  }
  return number;
}

template <class Pose>
int FleetSession<Pose>::AddLoopByStamp(int robot_a, std::int64_t stamp_a,
                                       int robot_b, std::int64_t stamp_b,
                                       const Pose& z,
                                       const Information& information) {
  const int number =
      fleet_.AddLoopByStamp(robot_a, stamp_a, robot_b, stamp_b, z, information);
  if (store_) {
    store_->RecordCandidateByStamp(number, robot_a, stamp_a, robot_b, stamp_b,
                                   z, information);
  }
  return number;
}

template <class Pose>
typename FleetSession<Pose>::Updated FleetSession<Pose>::Update(bool finish) {
  Updated updated;
  updated.changes = finish ? fleet_.Finish() : fleet_.Update();
  if (store_) {
    try {
      store_->CommitUpdate(finish, updated.changes);
    } catch (const SessionError& e) {
      updated.store_error = e.what();
    }
  }
  return updated;
}

template class FleetSession<Pose2>;
template class FleetSession<Pose3>;

}  // namespace rrr
