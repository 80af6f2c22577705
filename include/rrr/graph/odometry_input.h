// How a robot's odometry readings become keyframes and odometry edges.
#ifndef RRR_GRAPH_ODOMETRY_INPUT_H_
#define RRR_GRAPH_ODOMETRY_INPUT_H_

#include <cstdint>
#include <vector>

#include "rrr/graph/keyframe_track.h"
#include "rrr/graph/odometry_noise.h"

namespace rrr {

// The options of one robot's odometry stream, the same for a robot alone
// and for each robot of a fleet (Session).
struct OdometryInputOptions {
  // A reading makes a keyframe when it moved more than these from the
  // newest (both 0: every reading does); see KeyframeTrack.
  double keyframe_translation = 0.0;  // m
  double keyframe_rotation = 0.0;     // rad
  // An odometry edge's information (OdometryNoiseModel): from the change
  // of the readings' covariances if `use_odometry_covariance` and it is
  // positive definite, else from `odometry_information` (the diagonal, one
  // value per degree of freedom of the pose: of one metre or radian of
  // motion; empty: 100 each) times the motion, at least
  // `odometry_min_motion`.
  bool use_odometry_covariance = true;
  std::vector<double> odometry_information;
  double odometry_min_motion = 0.05;
  // A candidate's stamp names a keyframe at most this far from it.
  std::int64_t stamp_tolerance_ns = 100'000'000;
};

// Throws std::invalid_argument naming the option if `options` do not suit
// Pose: `odometry_information` of another size than Pose::kDof or with a
// value that is not positive, `odometry_min_motion` not positive, or (in
// KeyframeTrack's words) a keyframe threshold or the stamp tolerance
// negative.
template <class Pose>
void Validate(const OdometryInputOptions& options);

// The noise model of `options`, once they validate (else Validate throws).
template <class Pose>
OdometryNoiseModel<Pose> NoiseModelOf(const OdometryInputOptions& options);

// An empty keyframe track of `options`' thresholds, once they validate
// (else Validate throws).
template <class Pose>
KeyframeTrack<Pose> TrackOf(const OdometryInputOptions& options);

}  // namespace rrr

#endif  // RRR_GRAPH_ODOMETRY_INPUT_H_
