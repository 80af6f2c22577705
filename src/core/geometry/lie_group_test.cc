// Lie-group identities and Jacobians of Pose2 and Pose3, checked numerically.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <random>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"

namespace rrr {
namespace {

template <class Pose>
class LieGroupTest : public ::testing::Test {
 protected:
  using Tangent = typename Pose::Tangent;
  using Jacobian = typename Pose::Jacobian;

  // A random tangent vector whose rotation is below pi, where Log inverts Exp.
  Tangent RandomTangent(double scale) {
    Tangent xi;
    do {
      for (int k = 0; k < Pose::kDof; ++k) xi[k] = scale * normal_(rng_);
    } while (xi.template tail<Pose::kDof - Pose::kTranslationDim>().norm() >
             3.0);
    return xi;
  }
  // Central differences of f: Tangent -> Tangent at zero.
  template <class F>
  static Jacobian Numeric(F f) {
    constexpr double h = 1e-6;
    Jacobian j;
    for (int k = 0; k < Pose::kDof; ++k) {
      Tangent d = Tangent::Zero();
      d[k] = h;
      j.col(k) = (f(d) - f(-d)) / (2 * h);
    }
    return j;
  }
  static double Distance(const Pose& a, const Pose& b) {
    return a.between(b).Log().norm();
  }

  std::mt19937 rng_{42};
  std::normal_distribution<double> normal_;
};

using PoseTypes = ::testing::Types<Pose2, Pose3>;
TYPED_TEST_SUITE(LieGroupTest, PoseTypes);

TYPED_TEST(LieGroupTest, ExpLogRoundTrip) {
  for (const double scale : {1e-9, 1e-4, 0.3, 1.0}) {
    for (int trial = 0; trial < 20; ++trial) {
      auto xi = this->RandomTangent(scale);
      const TypeParam p = TypeParam::Exp(xi);
      EXPECT_LT((p.Log() - xi).norm(), 1e-9 * (1 + xi.norm()))
          << "scale " << scale;
    }
  }
}

TYPED_TEST(LieGroupTest, ComposeWithInverseIsIdentity) {
  for (int trial = 0; trial < 20; ++trial) {
    const TypeParam p = TypeParam::Exp(this->RandomTangent(1.0));
    EXPECT_LT((p * p.inverse()).Log().norm(), 1e-12);
    EXPECT_LT((p.inverse() * p).Log().norm(), 1e-12);
  }
}

TYPED_TEST(LieGroupTest, BetweenIsRelativePose) {
  const TypeParam a = TypeParam::Exp(this->RandomTangent(1.0));
  const TypeParam b = TypeParam::Exp(this->RandomTangent(1.0));
  EXPECT_LT(this->Distance(a * a.between(b), b), 1e-12);
}

TYPED_TEST(LieGroupTest, AdjointMovesPerturbationAcross) {
  for (int trial = 0; trial < 20; ++trial) {
    const TypeParam p = TypeParam::Exp(this->RandomTangent(1.0));
    const auto xi = this->RandomTangent(0.5);
    const TypeParam lhs = TypeParam::Exp(p.Adjoint() * xi) * p;
    const TypeParam rhs = p * TypeParam::Exp(xi);
    EXPECT_LT(this->Distance(lhs, rhs), 1e-10);
  }
}

TYPED_TEST(LieGroupTest, RightJacobianMatchesNumeric) {
  for (const double scale : {1e-8, 0.1, 1.0}) {
    for (int trial = 0; trial < 10; ++trial) {
      const auto xi = this->RandomTangent(scale);
      const TypeParam base = TypeParam::Exp(xi);
      // Exp(ξ + δ) = Exp(ξ) · Exp(Jr δ)  =>  Jr = d Log(Exp(ξ)⁻¹ Exp(ξ + δ)).
      const auto numeric = this->Numeric([&](const auto& d) {
        return base.between(TypeParam::Exp(xi + d)).Log();
      });
      EXPECT_LT((TypeParam::RightJacobian(xi) - numeric).norm(), 1e-6)
          << "scale " << scale;
      // Log(Exp(ξ) Exp(δ)) ≈ ξ + Jr⁻¹ δ.
      const auto numeric_inverse = this->Numeric(
          [&](const auto& d) { return (base * TypeParam::Exp(d)).Log(); });
      EXPECT_LT((TypeParam::RightJacobianInverse(xi) - numeric_inverse).norm(),
                1e-6)
          << "scale " << scale;
      EXPECT_LT(
          (TypeParam::RightJacobianInverse(xi) * TypeParam::RightJacobian(xi) -
           TypeParam::Jacobian::Identity())
              .norm(),
          1e-9);
    }
  }
}

TEST(Pose2, AngleIsWrapped) {
  EXPECT_NEAR(Pose2(0, 0, 3 * M_PI / 2).theta(), -M_PI / 2, 1e-12);
  EXPECT_NEAR(Pose2(0, 0, -M_PI).theta(), M_PI, 1e-12);
  EXPECT_NEAR(Pose2(0, 0, -0.5).angle(), 0.5, 1e-12);
}

TEST(Pose2, ComposeRotatesTranslation) {
  const Pose2 p = Pose2(1, 2, M_PI / 2) * Pose2(1, 0, 0);
  EXPECT_NEAR(p.x(), 1, 1e-12);
  EXPECT_NEAR(p.y(), 3, 1e-12);
  EXPECT_NEAR(p.theta(), M_PI / 2, 1e-12);
}

TYPED_TEST(LieGroupTest, CompositionStaysRigid) {
  // A frame found from poses that frames moved before, again and again (as
  // joining and splitting maps does): rounding must not grow into a scale.
  // p · p⁻¹ · p is p, but each round triples a rotation's relative error
  // unless composition keeps rotations rotations: 60 rounds turn 1e-16 into
  // more than 1.
  for (int trial = 0; trial < 10; ++trial) {
    TypeParam start;
    for (int k = 0; k < 10; ++k) {
      start = start * TypeParam::Exp(this->RandomTangent(0.5));
    }
    TypeParam p = start;
    for (int k = 0; k < 60; ++k) p = p * p.inverse() * p;
    EXPECT_LT((p.Log() - start.Log()).norm(), 1e-9);
    const TypeParam a = TypeParam::Exp(this->RandomTangent(1.0));
    const TypeParam b = TypeParam::Exp(this->RandomTangent(1.0));
    // Rigid: p moves two poses without changing their relative pose.
    EXPECT_LT(((p * a).between(p * b).Log() - a.between(b).Log()).norm(), 1e-9);
  }
}

TEST(Pose3, QuaternionSignDoesNotChangeLog) {
  const Eigen::Quaterniond q(Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitY()));
  const Pose3 a(q, Eigen::Vector3d(1, 2, 3));
  const Pose3 b(Eigen::Quaterniond(-q.coeffs()), Eigen::Vector3d(1, 2, 3));
  EXPECT_LT((a.Log() - b.Log()).norm(), 1e-12);
  EXPECT_NEAR(a.angle(), 0.7, 1e-12);
}

}  // namespace
}  // namespace rrr
