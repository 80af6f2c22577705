#include "msg_conversion.h"

#include <Eigen/LU>
#include <cmath>

#include "rrr/graph/covariance.h"

namespace rrr_ros {
namespace {

// No position coordinate of a robot's pose is this far from the origin (m);
// beyond it, pose arithmetic such as the logarithm can overflow.
constexpr double kFarthest = 1e9;

// Rows/columns of a 6x6 PoseWithCovariance covariance that a pose type uses.
template <class Pose>
constexpr std::array<int, Pose::kDof> kAxes();
template <>
constexpr std::array<int, 3> kAxes<rrr::Pose2>() {
  return {0, 1, 5};
}
template <>
constexpr std::array<int, 6> kAxes<rrr::Pose3>() {
  return {0, 1, 2, 3, 4, 5};
}

bool QuaternionFromRos(const geometry_msgs::Pose& in, Eigen::Quaterniond* q,
                       std::string* why) {
  const auto& o = in.orientation;
  const auto& p = in.position;
  for (const double v : {p.x, p.y, p.z, o.x, o.y, o.z, o.w}) {
    if (!std::isfinite(v)) {
      *why = "the pose has a value that is not finite";
      return false;
    }
  }
  for (const double v : {p.x, p.y, p.z}) {
    if (std::abs(v) > kFarthest) {
      *why = "the position has a coordinate of " + std::to_string(v) +
             " m, beyond " + std::to_string(kFarthest) + " m";
      return false;
    }
  }
  *q = Eigen::Quaterniond(o.w, o.x, o.y, o.z);
  if (std::abs(q->norm() - 1.0) > 1e-3) {
    *why = "the orientation is not a unit quaternion (norm " +
           std::to_string(q->norm()) + ")";
    return false;
  }
  return true;
}

}  // namespace

bool FromRos(const geometry_msgs::Pose& in, rrr::Pose2* out, std::string* why) {
  Eigen::Quaterniond q;
  if (!QuaternionFromRos(in, &q, why)) return false;
  const Eigen::Vector3d x = q.normalized() * Eigen::Vector3d::UnitX();
  *out = rrr::Pose2(in.position.x, in.position.y, std::atan2(x.y(), x.x()));
  return true;
}

bool FromRos(const geometry_msgs::Pose& in, rrr::Pose3* out, std::string* why) {
  Eigen::Quaterniond q;
  if (!QuaternionFromRos(in, &q, why)) return false;
  *out = rrr::Pose3(
      q, Eigen::Vector3d(in.position.x, in.position.y, in.position.z));
  return true;
}

geometry_msgs::Pose ToRos(const rrr::Pose2& pose) {
  geometry_msgs::Pose out;
  out.position.x = pose.x();
  out.position.y = pose.y();
  out.orientation.z = std::sin(pose.theta() / 2);
  out.orientation.w = std::cos(pose.theta() / 2);
  return out;
}

geometry_msgs::Pose ToRos(const rrr::Pose3& pose) {
  geometry_msgs::Pose out;
  out.position.x = pose.translation().x();
  out.position.y = pose.translation().y();
  out.position.z = pose.translation().z();
  out.orientation.x = pose.quaternion().x();
  out.orientation.y = pose.quaternion().y();
  out.orientation.z = pose.quaternion().z();
  out.orientation.w = pose.quaternion().w();
  return out;
}

template <class Pose>
geometry_msgs::Transform TransformOf(const Pose& pose) {
  const geometry_msgs::Pose p = ToRos(pose);
  geometry_msgs::Transform t;
  t.translation.x = p.position.x;
  t.translation.y = p.position.y;
  t.translation.z = p.position.z;
  t.rotation = p.orientation;
  return t;
}

geometry_msgs::Transform ToRosTransform(const rrr::Pose2& pose) {
  return TransformOf(pose);
}
geometry_msgs::Transform ToRosTransform(const rrr::Pose3& pose) {
  return TransformOf(pose);
}

template <class Pose>
bool InformationFromCovariance(const boost::array<double, 36>& covariance,
                               typename rrr::Constraint<Pose>::Information* out,
                               std::string* why) {
  constexpr auto axes = kAxes<Pose>();
  typename rrr::Constraint<Pose>::Information c;
  for (int r = 0; r < Pose::kDof; ++r) {
    for (int k = 0; k < Pose::kDof; ++k) {
      c(r, k) = covariance[axes[r] * 6 + axes[k]];
    }
  }
  if (!c.allFinite()) {
    *why = "the covariance has a value that is not finite";
    return false;
  }
  if (!c.isApprox(c.transpose(), 1e-9)) {
    *why = "the covariance is not symmetric";
    return false;
  }
  return rrr::InformationFromCovariance<Pose::kDof>(c, out, why);
}

template <class Pose>
boost::array<double, 36> CovarianceFromInformation(
    const typename rrr::Constraint<Pose>::Information& information) {
  constexpr auto axes = kAxes<Pose>();
  const typename rrr::Constraint<Pose>::Information c = information.inverse();
  boost::array<double, 36> out{};
  for (int r = 0; r < Pose::kDof; ++r) {
    for (int k = 0; k < Pose::kDof; ++k) out[axes[r] * 6 + axes[k]] = c(r, k);
  }
  return out;
}

template bool InformationFromCovariance<rrr::Pose2>(
    const boost::array<double, 36>&, rrr::Constraint<rrr::Pose2>::Information*,
    std::string*);
template bool InformationFromCovariance<rrr::Pose3>(
    const boost::array<double, 36>&, rrr::Constraint<rrr::Pose3>::Information*,
    std::string*);
template boost::array<double, 36> CovarianceFromInformation<rrr::Pose2>(
    const rrr::Constraint<rrr::Pose2>::Information&);
template boost::array<double, 36> CovarianceFromInformation<rrr::Pose3>(
    const rrr::Constraint<rrr::Pose3>::Information&);

rrr::OdometryCovariance FromRos(const boost::array<double, 36>& covariance) {
  return Eigen::Map<const Eigen::Matrix<double, 6, 6, Eigen::RowMajor>>(
      covariance.data());
}

boost::array<double, 36> ToRos(const rrr::OdometryCovariance& covariance) {
  boost::array<double, 36> out{};
  Eigen::Map<Eigen::Matrix<double, 6, 6, Eigen::RowMajor>>(out.data()) =
      covariance;
  return out;
}

}  // namespace rrr_ros
