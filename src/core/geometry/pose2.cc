#include "rrr/geometry/pose2.h"

#include <cmath>

#include <Eigen/LU>

namespace rrr {
namespace {

constexpr double kSmallAngle = 1e-6;

double WrapAngle(double a) {
  a = std::remainder(a, 2.0 * M_PI);
  return a <= -M_PI ? a + 2.0 * M_PI : a;
}

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
    : t_(x, y), theta_(WrapAngle(theta)) {}

Eigen::Matrix2d Pose2::rotation() const {
  const double c = std::cos(theta_), s = std::sin(theta_);
  Eigen::Matrix2d r;
  r << c, -s, s, c;
  return r;
}

Pose2 Pose2::operator*(const Pose2& other) const {
  const Translation t = t_ + rotation() * other.t_;
  return Pose2(t.x(), t.y(), theta_ + other.theta_);
}

Pose2 Pose2::inverse() const {
  const Translation t = -(rotation().transpose() * t_);
  return Pose2(t.x(), t.y(), -theta_);
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
