#include "rrr/graph/odometry_noise.h"

#include <Eigen/Cholesky>
#include <algorithm>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/graph/covariance.h"

namespace rrr {
namespace {

// The 6 odometry-frame coordinates (x y z rx ry rz) that each tangent
// coordinate of a pose corresponds to, and the rotation from the odometry
// frame into the pose's frame for them: 2D (x, y, θ) uses x, y, rz; 3D
// (ρ, φ) uses all six.
Eigen::Matrix<double, 3, 6> Select(const Pose2& pose) {
  Eigen::Matrix<double, 3, 6> s = Eigen::Matrix<double, 3, 6>::Zero();
  s.block<2, 2>(0, 0) = pose.rotation().transpose();
  s(2, 5) = 1.0;
  return s;
}

Eigen::Matrix<double, 6, 6> Select(const Pose3& pose) {
  Eigen::Matrix<double, 6, 6> s = Eigen::Matrix<double, 6, 6>::Zero();
  const Eigen::Matrix3d rt = pose.rotation().transpose();
  s.block<3, 3>(0, 0) = rt;
  s.block<3, 3>(3, 3) = rt;
  return s;
}

}  // namespace

template <class Pose>
OdometryNoiseModel<Pose>::OdometryNoiseModel(const Information& per_unit,
                                             double min_motion)
    : per_unit_(per_unit), min_motion_(min_motion) {}

template <class Pose>
typename OdometryNoiseModel<Pose>::Information
OdometryNoiseModel<Pose>::FromMotion(const Pose& motion) const {
  // The covariance per unit times the amount, inverted; stableNorm keeps a
  // long motion from overflowing.
  const double amount =
      std::max(motion.translation().stableNorm() + motion.angle(), min_motion_);
  return per_unit_ / amount;
}

template <class Pose>
typename OdometryNoiseModel<Pose>::Information
OdometryNoiseModel<Pose>::EdgeInformation(
    const Pose& from, const OdometryCovariance& from_cov, const Pose& to,
    const OdometryCovariance& to_cov, bool covariances, Source* source) const {
  if (covariances && from_cov.allFinite() && to_cov.allFinite()) {
    const auto s = Select(to);
    const Information change = s * (to_cov - from_cov) * s.transpose();
    Information information;
    if (InformationFromCovariance<Pose::kDof>(
            0.5 * (change + change.transpose()), &information)) {
      if (source) *source = Source::kCovarianceChange;
      return information;
    }
  }
  if (source) *source = Source::kMotion;
  return FromMotion(from.between(to));
}

template <class Pose>
OdometryCovariance OdometryNoiseModel<Pose>::Grow(
    const OdometryCovariance& from_cov, const Pose& to,
    const Information& information) {
  const auto s = Select(to);
  const Information step = information.ldlt().solve(Information::Identity());
  // s is orthogonal on its rows: sᵀ step s maps the step back to the
  // odometry frame's coordinates.
  OdometryCovariance grown = from_cov + s.transpose() * step * s;
  return 0.5 * (grown + grown.transpose());
}

template class OdometryNoiseModel<Pose2>;
template class OdometryNoiseModel<Pose3>;

}  // namespace rrr
