// The residual of an edge and its analytic Jacobians, checked numerically.
#include "rrr/solver/edge_error.h"

#include <gtest/gtest.h>

#include <random>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"

namespace rrr {
namespace {

template <class Pose>
class EdgeErrorTest : public ::testing::Test {
 protected:
  Pose RandomPose(double scale) {
    typename Pose::Tangent xi;
    for (int k = 0; k < Pose::kDof; ++k) xi[k] = scale * normal_(rng_);
    return Pose::Exp(xi);
  }
  std::mt19937 rng_{7};
  std::normal_distribution<double> normal_;
};

using PoseTypes = ::testing::Types<Pose2, Pose3>;
TYPED_TEST_SUITE(EdgeErrorTest, PoseTypes);

TYPED_TEST(EdgeErrorTest, ResidualIsZeroForExactMeasurement) {
  const TypeParam xi = this->RandomPose(1.0), xj = this->RandomPose(1.0);
  EXPECT_LT(EdgeResidual(xi.between(xj), xi, xj).norm(), 1e-12);
}

TYPED_TEST(EdgeErrorTest, JacobiansMatchNumericDerivatives) {
  using Tangent = typename TypeParam::Tangent;
  using Jacobian = typename TypeParam::Jacobian;
  constexpr double h = 1e-6;
  // Small and large residuals: false loops leave large ones.
  for (const double noise : {0.01, 1.0}) {
    for (int trial = 0; trial < 10; ++trial) {
      const TypeParam xi = this->RandomPose(2.0), xj = this->RandomPose(2.0);
      const TypeParam z = xi.between(xj) * this->RandomPose(noise);
      Jacobian ji, jj;
      EdgeResidualAndJacobians(z, xi, xj, &ji, &jj);
      Jacobian ni, nj;
      for (int k = 0; k < TypeParam::kDof; ++k) {
        Tangent d = Tangent::Zero();
        d[k] = h;
        const auto plus = TypeParam::Exp(d), minus = TypeParam::Exp(-d);
        ni.col(k) =
            (EdgeResidual(z, xi * plus, xj) - EdgeResidual(z, xi * minus, xj)) /
            (2 * h);
        nj.col(k) =
            (EdgeResidual(z, xi, xj * plus) - EdgeResidual(z, xi, xj * minus)) /
            (2 * h);
      }
      EXPECT_LT((ji - ni).norm(), 1e-6) << "noise " << noise;
      EXPECT_LT((jj - nj).norm(), 1e-6) << "noise " << noise;
    }
  }
}

}  // namespace
}  // namespace rrr
