#include "rrr/graph/odometry_input.h"

#include <stdexcept>
#include <string>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"

namespace rrr {

template <class Pose>
void Validate(const OdometryInputOptions& options) {
  const std::vector<double>& diagonal = options.odometry_information;
  if (!diagonal.empty() && diagonal.size() != static_cast<size_t>(Pose::kDof)) {
    throw std::invalid_argument("odometry_information needs " +
                                std::to_string(Pose::kDof) + " values, got " +
                                std::to_string(diagonal.size()));
  }
  for (const double d : diagonal) {
    if (!(d > 0.0)) {
      throw std::invalid_argument("odometry_information must be positive");
    }
  }
  if (!(options.odometry_min_motion > 0.0)) {
    throw std::invalid_argument("odometry_min_motion must be positive");
  }
  // The keyframe thresholds and the stamp tolerance: checked by the track.
  KeyframeTrack<Pose>(options.keyframe_translation, options.keyframe_rotation,
                      options.stamp_tolerance_ns);
}

template <class Pose>
OdometryNoiseModel<Pose> NoiseModelOf(const OdometryInputOptions& options) {
  Validate<Pose>(options);
  typename Constraint<Pose>::Information per_unit =
      Constraint<Pose>::Information::Identity() * 100.0;
  for (size_t k = 0; k < options.odometry_information.size(); ++k) {
    per_unit(k, k) = options.odometry_information[k];
  }
  return OdometryNoiseModel<Pose>(per_unit, options.odometry_min_motion);
}

template <class Pose>
KeyframeTrack<Pose> TrackOf(const OdometryInputOptions& options) {
  Validate<Pose>(options);
  return KeyframeTrack<Pose>(options.keyframe_translation,
                             options.keyframe_rotation,
                             options.stamp_tolerance_ns);
}

template void Validate<Pose2>(const OdometryInputOptions&);
template void Validate<Pose3>(const OdometryInputOptions&);
template OdometryNoiseModel<Pose2> NoiseModelOf(const OdometryInputOptions&);
template OdometryNoiseModel<Pose3> NoiseModelOf(const OdometryInputOptions&);
template KeyframeTrack<Pose2> TrackOf(const OdometryInputOptions&);
template KeyframeTrack<Pose3> TrackOf(const OdometryInputOptions&);

}  // namespace rrr
