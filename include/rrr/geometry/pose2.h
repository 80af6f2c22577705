// SE(2): rigid motions of the plane as a small value type.
#ifndef RRR_GEOMETRY_POSE2_H_
#define RRR_GEOMETRY_POSE2_H_

#include <Eigen/Core>
#include <array>
#include <cmath>

namespace rrr {

// A pose in the plane: rotation by `theta` (radians) then translation `t`.
// The tangent vector is ordered (x, y, theta), as in g2o's EDGE_SE2
// information matrices; perturbations are applied on the right:
// x ⊕ δ = x · Exp(δ).
class Pose2 {
 public:
  static constexpr int kDof = 3;
  static constexpr int kTranslationDim = 2;
  using Tangent = Eigen::Matrix<double, kDof, 1>;
  using Jacobian = Eigen::Matrix<double, kDof, kDof>;
  using Translation = Eigen::Vector2d;

  // The identity.
  Pose2() = default;
  // `theta` is wrapped to (-pi, pi].
  Pose2(double x, double y, double theta);

  double x() const { return t_.x(); }
  double y() const { return t_.y(); }
  double theta() const { return theta_; }
  const Translation& translation() const { return t_; }
  Eigen::Matrix2d rotation() const;

  // this · other.
  Pose2 operator*(const Pose2& other) const {
    const Translation t(t_.x() + cos_ * other.t_.x() - sin_ * other.t_.y(),
                        t_.y() + sin_ * other.t_.x() + cos_ * other.t_.y());
    return Pose2(t, theta_ + other.theta_,
                 cos_ * other.cos_ - sin_ * other.sin_,
                 sin_ * other.cos_ + cos_ * other.sin_);
  }
  Pose2 inverse() const {
    const Translation t(-(cos_ * t_.x() + sin_ * t_.y()),
                        sin_ * t_.x() - cos_ * t_.y());
    return Pose2(t, -theta_, cos_, -sin_);
  }
  // this⁻¹ · other: `other` seen from this pose.
  Pose2 between(const Pose2& other) const { return inverse() * other; }
  // Rotation angle of the pose in radians, in [0, pi].
  double angle() const;

  // The numbers the pose holds, bit for bit: x, y, theta and the cosine and
  // sine of theta as composition left them; FromParts gives the pose back
  // exactly (for saved states).
  using Parts = std::array<double, 5>;
  Parts parts() const { return {t_.x(), t_.y(), theta_, cos_, sin_}; }
  static Pose2 FromParts(const Parts& parts);

  static Pose2 Exp(const Tangent& xi);
  // Exact inverse of Exp for rotations in (-pi, pi].
  Tangent Log() const;
  // Adjoint: Exp(Ad · ξ) = this · Exp(ξ) · this⁻¹.
  Jacobian Adjoint() const;
  // Right Jacobian Jr(ξ): Exp(ξ + δ) ≈ Exp(ξ) · Exp(Jr(ξ) δ), and its inverse:
  // Log(Exp(ξ) · Exp(δ)) ≈ ξ + Jr⁻¹(ξ) δ.
  static Jacobian RightJacobian(const Tangent& xi);
  static Jacobian RightJacobianInverse(const Tangent& xi);

 private:
  // With cos and sin of theta known (composition needs no trigonometry),
  // scaled back to a rotation: rounding left in them would grow, composition
  // after composition, into a scale that no rigid motion has.
  Pose2(const Translation& t, double theta, double cos, double sin)
      : t_(t), theta_(WrapAngle(theta)) {
    const double norm = std::sqrt(cos * cos + sin * sin);
    cos_ = cos / norm;
    sin_ = sin / norm;
  }
  // `a` wrapped to (-pi, pi].
  static double WrapAngle(double a) {
    if (a > -M_PI && a <= M_PI) return a;
    a = std::remainder(a, 2.0 * M_PI);
    return a <= -M_PI ? a + 2.0 * M_PI : a;
  }

  Translation t_ = Translation::Zero();
  double theta_ = 0.0;
  double cos_ = 1.0, sin_ = 0.0;
};

}  // namespace rrr

#endif  // RRR_GEOMETRY_POSE2_H_
