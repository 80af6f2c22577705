#include "rrr/graph/odometry_noise.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"

namespace rrr {
namespace {

template <class Pose>
class OdometryNoiseTest : public ::testing::Test {};
using Poses = ::testing::Types<Pose2, Pose3>;
TYPED_TEST_SUITE(OdometryNoiseTest, Poses);

// A motion and a full (correlated) information matrix for it.
template <class Pose>
std::pair<Pose, typename Constraint<Pose>::Information> Step(int k) {
  typename Pose::Tangent xi = Pose::Tangent::Zero();
  xi[0] = 1.0;
  xi[Pose::kDof - 1] = 0.3 * k;
  typename Constraint<Pose>::Information a =
      Constraint<Pose>::Information::Random();
  return {Pose::Exp(xi), a * a.transpose() * 10.0 +
                             Constraint<Pose>::Information::Identity() * 50.0};
}

TYPED_TEST(OdometryNoiseTest, AGrowingCovarianceGivesBackEachStep) {
  using Model = OdometryNoiseModel<TypeParam>;
  const Model model(Constraint<TypeParam>::Information::Identity(), 0.05);
  OdometryCovariance covariance = OdometryCovariance::Identity() * 1e-3;
  TypeParam pose;
  for (int k = 1; k < 30; ++k) {
    const auto [motion, information] = Step<TypeParam>(k);
    const TypeParam next = pose * motion;
    const OdometryCovariance grown = Model::Grow(covariance, next, information);
    typename Model::Source source;
    const auto recovered =
        model.EdgeInformation(pose, covariance, next, grown, true, &source);
    EXPECT_EQ(source, Model::Source::kCovarianceChange);
    EXPECT_LT((recovered - information).norm(), 1e-6 * information.norm())
        << "step " << k;
    pose = next;
    covariance = grown;
  }
}

TYPED_TEST(OdometryNoiseTest, AConstantCovarianceFallsBackToTheMotion) {
  using Model = OdometryNoiseModel<TypeParam>;
  const auto per_unit = Constraint<TypeParam>::Information::Identity() * 100.0;
  const Model model(per_unit, 0.05);
  const OdometryCovariance constant = OdometryCovariance::Identity() * 0.01;
  typename TypeParam::Tangent xi = TypeParam::Tangent::Zero();
  xi[0] = 2.0;  // two metres straight on
  const TypeParam from, to = TypeParam::Exp(xi);
  typename Model::Source source;
  const auto information =
      model.EdgeInformation(from, constant, to, constant, true, &source);
  EXPECT_EQ(source, Model::Source::kMotion);
  EXPECT_LT((information - per_unit / 2.0).norm(), 1e-9);
  // Not asked to use covariances: the motion rule, whatever they say.
  model.EdgeInformation(from, constant, to, constant * 2.0, false, &source);
  EXPECT_EQ(source, Model::Source::kMotion);
  // Standing still: at least min_motion.
  EXPECT_LT((model.FromMotion(TypeParam()) - per_unit / 0.05).norm(), 1e-6);
}

TYPED_TEST(OdometryNoiseTest, ANumericallySingularChangeFallsBackToTheMotion) {
  // Two changes that are positive definite (each passes a Cholesky test) but
  // numerically singular: the inverse of one would overflow, the other's
  // condition number is 10^20 (both fail the reciprocal-condition test).
  using Model = OdometryNoiseModel<TypeParam>;
  const auto per_unit = Constraint<TypeParam>::Information::Identity() * 100.0;
  const Model model(per_unit, 0.05);
  typename TypeParam::Tangent xi = TypeParam::Tangent::Zero();
  xi[0] = 2.0;
  const OdometryCovariance none = OdometryCovariance::Zero();
  OdometryCovariance ill = OdometryCovariance::Identity();
  ill(5, 5) = 1e-20;  // rz: a coordinate of both 2D and 3D poses
  for (const OdometryCovariance& grown :
       {OdometryCovariance(OdometryCovariance::Identity() * 1e-310), ill}) {
    ASSERT_EQ(grown.llt().info(), Eigen::Success);
    typename Model::Source source;
    const auto information = model.EdgeInformation(
        TypeParam(), none, TypeParam::Exp(xi), grown, true, &source);
    EXPECT_EQ(source, Model::Source::kMotion) << grown(5, 5);
    EXPECT_TRUE(information.allFinite());
    EXPECT_EQ(information.llt().info(), Eigen::Success);
    EXPECT_LT((information - per_unit / 2.0).norm(), 1e-9);
  }
}

TYPED_TEST(OdometryNoiseTest, AVeryLongMotionStillHasFiniteInformation) {
  using Model = OdometryNoiseModel<TypeParam>;
  // Found by fuzzing the message conversion: the motion rule's length
  // overflowed and the information was left unset.
  const Model model(Constraint<TypeParam>::Information::Identity(), 0.05);
  typename TypeParam::Tangent xi = TypeParam::Tangent::Zero();
  xi[0] = 1e200;  // its squared length overflows
  const auto information = model.FromMotion(TypeParam::Exp(xi));
  EXPECT_TRUE(information.allFinite());
  EXPECT_GT(information(0, 0), 0.0);
}

TEST(OdometryNoise, AShrinkingOrBrokenCovarianceFallsBackToTheMotion) {
  const OdometryNoiseModel<Pose2> model(Pose2::Jacobian::Identity(), 0.05);
  const OdometryCovariance big = OdometryCovariance::Identity();
  OdometryCovariance nan = big;
  nan(0, 0) = std::nan("");
  OdometryNoiseModel<Pose2>::Source source;
  model.EdgeInformation(Pose2(), big, Pose2(1, 0, 0), big * 0.5, true, &source);
  EXPECT_EQ(source, OdometryNoiseModel<Pose2>::Source::kMotion);
  model.EdgeInformation(Pose2(), big, Pose2(1, 0, 0), nan, true, &source);
  EXPECT_EQ(source, OdometryNoiseModel<Pose2>::Source::kMotion);
}

}  // namespace
}  // namespace rrr
