// SE(3): rigid motions of space as a small value type.
#ifndef RRR_GEOMETRY_POSE3_H_
#define RRR_GEOMETRY_POSE3_H_

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>

namespace rrr {

// A pose in space: rotation `q` (unit quaternion) then translation `t`.
// The tangent vector is ordered (ρ, φ) = (translation part, rotation vector),
// matching the (x y z qx qy qz) order of g2o's EDGE_SE3:QUAT information
// matrices; perturbations are applied on the right: x ⊕ δ = x · Exp(δ).
class Pose3 {
 public:
  static constexpr int kDof = 6;
  static constexpr int kTranslationDim = 3;
  using Tangent = Eigen::Matrix<double, kDof, 1>;
  using Jacobian = Eigen::Matrix<double, kDof, kDof>;
  using Translation = Eigen::Vector3d;

  // The identity.
  Pose3() = default;
  // `q` is normalized.
  Pose3(const Eigen::Quaterniond& q, const Eigen::Vector3d& t);

  const Eigen::Quaterniond& quaternion() const { return q_; }
  const Translation& translation() const { return t_; }
  Eigen::Matrix3d rotation() const { return q_.toRotationMatrix(); }

  // The numbers the pose holds, bit for bit: the quaternion's w, x, y, z and
  // the translation; FromParts gives the pose back exactly (for saved
  // states; the quaternion is not normalized again).
  using Parts = std::array<double, 7>;
  Parts parts() const {
    return {q_.w(), q_.x(), q_.y(), q_.z(), t_.x(), t_.y(), t_.z()};
  }
  static Pose3 FromParts(const Parts& parts);

  // this · other.
  Pose3 operator*(const Pose3& other) const;
  Pose3 inverse() const;
  // this⁻¹ · other: `other` seen from this pose.
  Pose3 between(const Pose3& other) const { return inverse() * other; }
  // Rotation angle of the pose in radians, in [0, pi].
  double angle() const;

  static Pose3 Exp(const Tangent& xi);
  // Inverse of Exp; the rotation vector has norm in [0, pi].
  Tangent Log() const;
  // Adjoint: Exp(Ad · ξ) = this · Exp(ξ) · this⁻¹.
  Jacobian Adjoint() const;
  // Right Jacobian Jr(ξ): Exp(ξ + δ) ≈ Exp(ξ) · Exp(Jr(ξ) δ), and its inverse:
  // Log(Exp(ξ) · Exp(δ)) ≈ ξ + Jr⁻¹(ξ) δ.
  static Jacobian RightJacobian(const Tangent& xi);
  static Jacobian RightJacobianInverse(const Tangent& xi);

 private:
  Eigen::Quaterniond q_ = Eigen::Quaterniond::Identity();
  Translation t_ = Translation::Zero();
};

}  // namespace rrr

#endif  // RRR_GEOMETRY_POSE3_H_
