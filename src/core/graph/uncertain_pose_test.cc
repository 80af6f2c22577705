#include "rrr/graph/uncertain_pose.h"

#include <gtest/gtest.h>

#include <random>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"

namespace rrr {
namespace {

TEST(UncertainPose, ACycleOfAgreeingMeasurementsIsAtDistanceZero) {
  const Pose3 a =
      Pose3::Exp((Pose3::Tangent() << 1, 2, 0.5, 0.1, -0.2, 0.3).finished());
  const Pose3 b =
      Pose3::Exp((Pose3::Tangent() << -3, 0.2, 1, 0.4, 0.1, -0.6).finished());
  const Pose3::Jacobian cov = 0.01 * Pose3::Jacobian::Identity();
  const UncertainPose<Pose3> ab{a * b, cov}, x{a, cov}, y{b, cov};
  const UncertainPose<Pose3> cycle = x * y * ab.Inverse();
  EXPECT_NEAR(cycle.SquaredDistance(), 0.0, 1e-12);
}

TEST(UncertainPose, ACycleOffAlongXIsAtItsSquaredDistanceOverItsVariance) {
  // Steps along x: the variance along x adds up (0.01 m² each, nothing
  // else correlates with it), and the cycle misses by 0.3 m.
  const auto along_x = [](double x) {
    return Pose3::Exp((Pose3::Tangent() << x, 0, 0, 0, 0, 0).finished());
  };
  Pose3::Tangent variances;
  variances << 0.01, 0.01, 0.01, 1e-4, 1e-4, 1e-4;
  const Pose3::Jacobian cov = variances.asDiagonal();
  const UncertainPose<Pose3> x{along_x(1.0), cov}, y{along_x(2.0), cov};
  const UncertainPose<Pose3> off{along_x(3.3), cov};
  EXPECT_NEAR((x * y * off.Inverse()).SquaredDistance(), 0.09 / 0.03, 1e-9);
}

TEST(UncertainPose, CompositionMatchesSampledCovarianceToFirstOrder) {
  // Two uncertain planar steps composed; the covariance of the composition
  // against that of 20,000 samples.
  const UncertainPose<Pose2> x{Pose2(2.0, 0.5, 0.4),
                               Eigen::Vector3d(1e-4, 4e-4, 1e-4).asDiagonal()};
  const UncertainPose<Pose2> y{Pose2(1.0, -1.0, -0.2),
                               Eigen::Vector3d(9e-4, 1e-4, 4e-4).asDiagonal()};
  const UncertainPose<Pose2> xy = x * y;
  std::mt19937 rng(1);
  std::normal_distribution<double> n(0.0, 1.0);
  const auto draw = [&](const UncertainPose<Pose2>& u) {
    const Eigen::Matrix3d l = u.cov.llt().matrixL();
    return u.pose * Pose2::Exp(l * Eigen::Vector3d(n(rng), n(rng), n(rng)));
  };
  Eigen::Matrix3d sampled = Eigen::Matrix3d::Zero();
  const int samples = 20000;
  for (int s = 0; s < samples; ++s) {
    const Eigen::Vector3d e = xy.pose.between(draw(x) * draw(y)).Log();
    sampled += e * e.transpose() / samples;
  }
  EXPECT_LT((sampled - xy.cov).norm(), 0.05 * xy.cov.norm());
}

TEST(UncertainPose, OdometryBetweenIsCertainOnOnePoseAndInvertsBackwards) {
  OdometryChain<Pose2> chain;
  const Eigen::Matrix3d information = 100.0 * Eigen::Matrix3d::Identity();
  for (int k = 0; k < 5; ++k) chain.Append(Pose2(1.0, 0.0, 0.1), information);
  EXPECT_EQ(OdometryBetween(chain, 2, 2).cov.norm(), 0.0);
  const UncertainPose<Pose2> forward = OdometryBetween(chain, 1, 4);
  const UncertainPose<Pose2> backward = OdometryBetween(chain, 4, 1);
  EXPECT_NEAR((forward * backward).pose.Log().norm(), 0.0, 1e-12);
  EXPECT_TRUE(forward.cov.isApprox(chain.CovarianceBetween(1, 4)));
  EXPECT_GT(forward.cov.trace(), OdometryBetween(chain, 1, 2).cov.trace());
}

}  // namespace
}  // namespace rrr
