#include "rrr/graph/odometry_input.h"

#include <stdexcept>
#include <string>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"

namespace rrr {

template <class Pose>
OdometryNoiseModel<Pose> NoiseModelOf(const OdometryInputOptions& options) {
  using Information = typename Constraint<Pose>::Information;
  const std::vector<double>& diagonal = options.odometry_information;
  Information per_unit = Information::Identity() * 100.0;
  if (!diagonal.empty()) {
    if (diagonal.size() != static_cast<size_t>(Pose::kDof)) {
      throw std::invalid_argument("odometry_information needs " +
                                  std::to_string(Pose::kDof) + " values, got " +
                                  std::to_string(diagonal.size()));
    }
    for (int k = 0; k < Pose::kDof; ++k) {
      if (!(diagonal[k] > 0.0)) {
        throw std::invalid_argument("odometry_information must be positive");
      }
      per_unit(k, k) = diagonal[k];
    }
  }
  if (!(options.odometry_min_motion > 0.0)) {
    throw std::invalid_argument("odometry_min_motion must be positive");
  }
  return OdometryNoiseModel<Pose>(per_unit, options.odometry_min_motion);
}

template <class Pose>
KeyframeTrack<Pose> TrackOf(const OdometryInputOptions& options) {
  if (options.stamp_tolerance_ns < 0) {
    throw std::invalid_argument("stamp_tolerance_ns must not be negative");
  }
  return KeyframeTrack<Pose>(options.keyframe_translation,
                             options.keyframe_rotation,
                             options.stamp_tolerance_ns);
}

template OdometryNoiseModel<Pose2> NoiseModelOf(const OdometryInputOptions&);
template OdometryNoiseModel<Pose3> NoiseModelOf(const OdometryInputOptions&);
template KeyframeTrack<Pose2> TrackOf(const OdometryInputOptions&);
template KeyframeTrack<Pose3> TrackOf(const OdometryInputOptions&);

}  // namespace rrr
