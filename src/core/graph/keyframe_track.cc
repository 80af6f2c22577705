#include "rrr/graph/keyframe_track.h"

#include <stdexcept>
#include <string>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"

namespace rrr {

template <class Pose>
KeyframeTrack<Pose>::KeyframeTrack(double translation, double rotation,
                                   std::int64_t stamp_tolerance_ns)
    : translation_(translation),
      rotation_(rotation),
      stamps_(stamp_tolerance_ns) {
  if (!(translation >= 0.0) || !(rotation >= 0.0)) {
    throw std::invalid_argument(
        "the keyframe thresholds must not be negative, got " +
        std::to_string(translation) + " m and " + std::to_string(rotation) +
        " rad");
  }
}

template <class Pose>
typename KeyframeTrack<Pose>::Reading KeyframeTrack<Pose>::Judge(
    const KeyframeRecord<Pose>& reading) const {
  Reading out;
  if (empty()) {
    out.keyframe = true;
    return out;
  }
  if (reading.stamp_ns < stamps_.newest()) {
    out.problem = "its stamp is older than the last keyframe's";
    return out;
  }
  out.motion = odometry_.back().between(reading.odometry_pose);
  if (!out.motion.Log().allFinite()) {
    out.problem = "the motion from the last keyframe is not finite";
    return out;
  }
  const bool every = translation_ == 0.0 && rotation_ == 0.0;
  out.keyframe = every || out.motion.translation().norm() > translation_ ||
                 out.motion.angle() > rotation_;
  return out;
}

template <class Pose>
void KeyframeTrack<Pose>::Append(const KeyframeRecord<Pose>& keyframe) {
  const Reading reading = Judge(keyframe);
  if (!reading.problem.empty()) {
    throw std::invalid_argument("keyframe " + std::to_string(size()) + ": " +
                                reading.problem);
  }
  stamps_.Append(keyframe.stamp_ns);
  map_.push_back(map_.empty() ? keyframe.odometry_pose
                              : map_.back() * reading.motion);
  odometry_.push_back(keyframe.odometry_pose);
  newest_covariance_ = keyframe.covariance;
}

template <class Pose>
KeyframeRecord<Pose> KeyframeTrack<Pose>::newest() const {
  return {stamps_.newest(), odometry_.back(), newest_covariance_};
}

template <class Pose>
void KeyframeTrack<Pose>::SetMap(const std::vector<Pose>& estimates) {
  if (estimates.size() != odometry_.size()) {
    throw std::invalid_argument(
        "a map of " + std::to_string(estimates.size()) + " poses for " +
        std::to_string(odometry_.size()) + " keyframes");
  }
  if (estimates.empty()) return;
  const Pose shift = odometry_.front() * estimates.front().inverse();
  map_.clear();
  for (const Pose& p : estimates) map_.push_back(shift * p);
}

template <class Pose>
void KeyframeTrack<Pose>::SetNewest(const Pose& first, const Pose& newest) {
  if (empty()) throw std::logic_error("SetNewest on an empty keyframe track");
  map_.back() = odometry_.front() * first.inverse() * newest;
}

template <class Pose>
Pose KeyframeTrack<Pose>::MapToOdom() const {
  if (empty()) return Pose();
  return map_.back() * odometry_.back().inverse();
}

template class KeyframeTrack<Pose2>;
template class KeyframeTrack<Pose3>;

}  // namespace rrr
