// The information of an odometry edge, from what an odometry source's pose
// covariance means.
#ifndef RRR_GRAPH_ODOMETRY_NOISE_H_
#define RRR_GRAPH_ODOMETRY_NOISE_H_

#include <Eigen/Core>
#include <string>

#include "rrr/graph/pose_graph.h"

namespace rrr {

// A pose covariance in the odometry frame, as nav_msgs/Odometry carries it:
// 6 × 6 over (x, y, z, rotation about x, y, z), the rotations fixed-axis in
// the odometry frame.
using OdometryCovariance = Eigen::Matrix<double, 6, 6>;

// Finds the information of the odometry edge between two keyframes. An
// odometry source reports the covariance of its pose in the odometry frame:
// it grows as the robot moves (a filter such as robot_localization) or stays
// constant (many drivers, such as diff_drive_controller). The edge needs the
// covariance of the motion between the keyframes, in the frame of the later
// one (the residual Log(z⁻¹ x_i⁻¹ x_j) perturbs x_j on the right):
//  - when the change of the pose covariance between the keyframes is
//    positive definite, it is that change, rotated into the later keyframe's
//    frame (to first order, the covariance the source added over the motion);
//  - otherwise (constant, shrinking or missing covariances), the covariance
//    of `per_unit` (the information of one metre or one radian of motion)
//    times max(metres + radians travelled, `min_motion`).
template <class Pose>
class OdometryNoiseModel {
 public:
  using Information = typename Constraint<Pose>::Information;

  // `per_unit` must be symmetric positive definite, `min_motion` > 0.
  OdometryNoiseModel(const Information& per_unit, double min_motion);

  // How the last information was found.
  enum class Source { kCovarianceChange, kMotion };

  // The information of the edge from keyframe `from` to keyframe `to` (their
  // poses in the odometry frame), with their reported covariances if
  // `covariances` is true. Sets `*source` if given. The result is symmetric
  // positive definite whenever the motion between the poses is finite: a
  // change of covariance that is not (numerically) positive definite falls
  // back to the motion rule.
  Information EdgeInformation(const Pose& from,
                              const OdometryCovariance& from_cov,
                              const Pose& to, const OdometryCovariance& to_cov,
                              bool covariances, Source* source = nullptr) const;
  // The information of a motion `motion` from its length alone.
  Information FromMotion(const Pose& motion) const;

  // The pose covariance a growing source reports at `to` when it reported
  // `from_cov` at the previous keyframe and the motion between them has the
  // covariance of `information` (in the later keyframe's frame): the inverse
  // of EdgeInformation's first rule (rrr to-bag writes this).
  static OdometryCovariance Grow(const OdometryCovariance& from_cov,
                                 const Pose& to,
                                 const Information& information);

 private:
  Information per_unit_;  // the information of one unit of motion
  double min_motion_;
};

}  // namespace rrr

#endif  // RRR_GRAPH_ODOMETRY_NOISE_H_
