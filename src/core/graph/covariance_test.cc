#include "rrr/graph/covariance.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace rrr {
namespace {

using ::testing::HasSubstr;

TEST(Covariance, AWellConditionedCovarianceGivesItsInverse) {
  Eigen::Matrix3d covariance;
  covariance << 4, 1, 0, 1, 2, 0, 0, 0, 0.5;
  Eigen::Matrix3d information;
  ASSERT_TRUE(InformationFromCovariance<3>(covariance, &information));
  EXPECT_LT((information * covariance - Eigen::Matrix3d::Identity()).norm(),
            1e-12);
  EXPECT_EQ(information, information.transpose());
}

TEST(Covariance, UnusableCovariancesAreRefusedWithTheReason) {
  const Eigen::Matrix<double, 6, 6> untouched =
      Eigen::Matrix<double, 6, 6>::Identity() * 7.0;
  Eigen::Matrix<double, 6, 6> information = untouched;
  std::string why;
  Eigen::Matrix<double, 6, 6> indefinite =
      Eigen::Matrix<double, 6, 6>::Identity();
  indefinite(2, 2) = -1.0;
  EXPECT_FALSE(InformationFromCovariance<6>(indefinite, &information, &why));
  EXPECT_THAT(why, HasSubstr("not positive definite"));
  Eigen::Matrix<double, 6, 6> singular =
      Eigen::Matrix<double, 6, 6>::Identity();
  singular(0, 0) = 1e-20;
  EXPECT_FALSE(InformationFromCovariance<6>(singular, &information, &why));
  EXPECT_THAT(why, HasSubstr("numerically singular"));
  // Subnormal variances: their inverse would overflow.
  EXPECT_FALSE(InformationFromCovariance<6>(
      Eigen::Matrix<double, 6, 6>::Identity() * 1e-310, &information, &why));
  EXPECT_EQ(information, untouched);
}

}  // namespace
}  // namespace rrr
