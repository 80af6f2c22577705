#include "rrr/geometry/pose3.h"

#include <cmath>

namespace rrr {
namespace {

constexpr double kSmallAngle = 1e-5;

using Matrix3 = Eigen::Matrix3d;
using Vector3 = Eigen::Vector3d;

Matrix3 Hat(const Vector3& v) {
  Matrix3 m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

// Left Jacobian of SO(3) and its inverse.
Matrix3 SO3LeftJacobian(const Vector3& phi) {
  const double th = phi.norm();
  const Matrix3 w = Hat(phi);
  if (th < kSmallAngle) return Matrix3::Identity() + 0.5 * w + w * w / 6.0;
  const double th2 = th * th;
  return Matrix3::Identity() + (1.0 - std::cos(th)) / th2 * w +
         (th - std::sin(th)) / (th2 * th) * w * w;
}

Matrix3 SO3LeftJacobianInverse(const Vector3& phi) {
  const double th = phi.norm();
  const Matrix3 w = Hat(phi);
  if (th < kSmallAngle) return Matrix3::Identity() - 0.5 * w + w * w / 12.0;
  const double coef =
      1.0 / (th * th) - (1.0 + std::cos(th)) / (2.0 * th * std::sin(th));
  return Matrix3::Identity() - 0.5 * w + coef * w * w;
}

Eigen::Quaterniond SO3Exp(const Vector3& phi) {
  const double th = phi.norm();
  if (th < kSmallAngle) {
    Eigen::Quaterniond q(1.0, phi.x() / 2, phi.y() / 2, phi.z() / 2);
    return q.normalized();
  }
  return Eigen::Quaterniond(Eigen::AngleAxisd(th, phi / th));
}

Vector3 SO3Log(const Eigen::Quaterniond& q_in) {
  // Use the representative with w >= 0 so the angle is in [0, pi].
  const Eigen::Quaterniond q =
      q_in.w() < 0 ? Eigen::Quaterniond(-q_in.coeffs()) : q_in;
  const double n = q.vec().norm();
  if (n < 1e-10) return 2.0 * q.vec() / q.w();
  return 2.0 * std::atan2(n, q.w()) / n * q.vec();
}

// The Q block of the SE(3) left Jacobian for ξ = (ρ, φ) (Barfoot, 2017).
Matrix3 LeftJacobianQ(const Vector3& rho, const Vector3& phi) {
  const Matrix3 p = Hat(phi), r = Hat(rho);
  const double th = phi.norm();
  double c1, c2, c3;
  if (th < kSmallAngle) {
    c1 = 1.0 / 6.0;
    c2 = 1.0 / 24.0;
    c3 = 1.0 / 120.0;
  } else {
    const double th2 = th * th, s = std::sin(th), c = std::cos(th);
    c1 = (th - s) / (th2 * th);
    c2 = (th2 + 2.0 * c - 2.0) / (2.0 * th2 * th2);
    c3 = (2.0 * th - 3.0 * s + th * c) / (2.0 * th2 * th2 * th);
  }
  return 0.5 * r + c1 * (p * r + r * p + p * r * p) +
         c2 * (p * p * r + r * p * p - 3.0 * p * r * p) +
         c3 * (p * r * p * p + p * p * r * p);
}

}  // namespace

Pose3::Pose3(const Eigen::Quaterniond& q, const Eigen::Vector3d& t)
    : q_(q.normalized()), t_(t) {}

Pose3 Pose3::FromParts(const Parts& parts) {
  Pose3 p;
  p.q_ = Eigen::Quaterniond(parts[0], parts[1], parts[2], parts[3]);
  p.t_ << parts[4], parts[5], parts[6];
  return p;
}

Pose3 Pose3::operator*(const Pose3& other) const {
  return Pose3(q_ * other.q_, t_ + q_ * other.t_);
}

Pose3 Pose3::inverse() const {
  const Eigen::Quaterniond qi = q_.conjugate();
  return Pose3(qi, -(qi * t_));
}

double Pose3::angle() const { return SO3Log(q_).norm(); }

Pose3 Pose3::Exp(const Tangent& xi) {
  const Vector3 rho = xi.head<3>(), phi = xi.tail<3>();
  return Pose3(SO3Exp(phi), SO3LeftJacobian(phi) * rho);
}

Pose3::Tangent Pose3::Log() const {
  const Vector3 phi = SO3Log(q_);
  Tangent xi;
  xi << SO3LeftJacobianInverse(phi) * t_, phi;
  return xi;
}

Pose3::Jacobian Pose3::Adjoint() const {
  const Matrix3 r = rotation();
  Jacobian ad = Jacobian::Zero();
  ad.topLeftCorner<3, 3>() = r;
  ad.bottomRightCorner<3, 3>() = r;
  ad.topRightCorner<3, 3>() = Hat(t_) * r;
  return ad;
}

Pose3::Jacobian Pose3::RightJacobian(const Tangent& xi) {
  // Jr(ξ) = Jl(-ξ).
  const Vector3 rho = -xi.head<3>(), phi = -xi.tail<3>();
  const Matrix3 j = SO3LeftJacobian(phi);
  Jacobian out = Jacobian::Zero();
  out.topLeftCorner<3, 3>() = j;
  out.bottomRightCorner<3, 3>() = j;
  out.topRightCorner<3, 3>() = LeftJacobianQ(rho, phi);
  return out;
}

Pose3::Jacobian Pose3::RightJacobianInverse(const Tangent& xi) {
  const Vector3 rho = -xi.head<3>(), phi = -xi.tail<3>();
  const Matrix3 ji = SO3LeftJacobianInverse(phi);
  Jacobian out = Jacobian::Zero();
  out.topLeftCorner<3, 3>() = ji;
  out.bottomRightCorner<3, 3>() = ji;
  out.topRightCorner<3, 3>() = -ji * LeftJacobianQ(rho, phi) * ji;
  return out;
}

}  // namespace rrr
