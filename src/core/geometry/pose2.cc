#include "rrr/geometry/pose2.h"

#include <Eigen/LU>
#include <cmath>

namespace rrr {
namespace {

constexpr double kSmallAngle = 1e-6;

// sin(θ)/θ and (1 - cos(θ))/θ, with their limits near zero.
void SinCosTerms(double theta, double* s, double* c) {
  if (std::abs(theta) < kSmallAngle) {
    *s = 1.0 - theta * theta / 6.0;
    *c = theta / 2.0;
  } else {
    *s = std::sin(theta) / theta;
    *c = (1.0 - std::cos(theta)) / theta;
  }
}

}  // namespace

Pose2::Pose2(double x, double y, double theta)
    : t_(x, y),
      theta_(WrapAngle(theta)),
      cos_(std::cos(theta_)),
      sin_(std::sin(theta_)) {}

Pose2 Pose2::FromParts(const Parts& parts) {
  Pose2 p;
  p.t_ << parts[0], parts[1];
  p.theta_ = parts[2];
  p.cos_ = parts[3];
  p.sin_ = parts[4];
  return p;
}

Eigen::Matrix2d Pose2::rotation() const {
  Eigen::Matrix2d r;
  r << cos_, -sin_, sin_, cos_;
  return r;
}

double Pose2::angle() const { return std::abs(theta_); }

Pose2 Pose2::Exp(const Tangent& xi) {
  double s, c;
  SinCosTerms(xi.z(), &s, &c);
  return Pose2(s * xi.x() - c * xi.y(), c * xi.x() + s * xi.y(), xi.z());
}

Pose2::Tangent Pose2::Log() const {
  double s, c;
  SinCosTerms(theta_, &s, &c);
  // V = [s -c; c s]; V⁻¹ = [s c; -c s] / (s² + c²).
  const double det = s * s + c * c;
  Tangent xi;
  xi << (s * t_.x() + c * t_.y()) / det, (-c * t_.x() + s * t_.y()) / det,
      theta_;
  return xi;
}

Pose2::Jacobian Pose2::Adjoint() const {
  Jacobian ad = Jacobian::Identity();
  ad.topLeftCorner<2, 2>() = rotation();
  ad(0, 2) = t_.y();
  ad(1, 2) = -t_.x();
  return ad;
}

Pose2::Jacobian Pose2::RightJacobian(const Tangent& xi) {
  const double x = xi.x(), y = xi.y(), th = xi.z();
  double s, c;
  SinCosTerms(th, &s, &c);
  Jacobian j = Jacobian::Identity();
  j(0, 0) = s;
  j(0, 1) = c;
  j(1, 0) = -c;
  j(1, 1) = s;
  if (std::abs(th) < kSmallAngle) {
    j(0, 2) = -y / 2.0 + x * th / 6.0;
    j(1, 2) = x / 2.0 + y * th / 6.0;
  } else {
    const double th2 = th * th;
    j(0, 2) = (th * x - y + y * std::cos(th) - x * std::sin(th)) / th2;
    j(1, 2) = (x + th * y - x * std::cos(th) - y * std::sin(th)) / th2;
  }
  return j;
}

Pose2::Jacobian Pose2::RightJacobianInverse(const Tangent& xi) {
  return RightJacobian(xi).inverse();
}

}  // namespace rrr
