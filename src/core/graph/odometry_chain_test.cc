#include "rrr/graph/odometry_chain.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/solver/edge_error.h"

namespace rrr {
namespace {

// A chain of `n` random steps with random information matrices.
template <class Pose>
struct RandomChain {
  static constexpr int D = Pose::kDof;
  std::vector<Pose> steps;
  std::vector<Eigen::Matrix<double, D, D>> information;

  explicit RandomChain(int n) {
    std::mt19937 rng(7);
    std::normal_distribution<double> normal(0.0, 1.0);
    for (int k = 0; k < n; ++k) {
      typename Pose::Tangent xi;
      for (int a = 0; a < D; ++a) xi[a] = 0.3 * normal(rng);
      xi[0] += 1.0;
      Eigen::Matrix<double, D, D> a;
      for (int r = 0; r < D; ++r)
        for (int c = 0; c < D; ++c) a(r, c) = normal(rng);
      steps.push_back(Pose::Exp(xi));
      information.push_back(a * a.transpose() +
                            5.0 * Eigen::Matrix<double, D, D>::Identity());
    }
  }
  OdometryChain<Pose> Chain() const {
    OdometryChain<Pose> chain;
    for (size_t k = 0; k < steps.size(); ++k) {
      chain.Append(steps[k], information[k]);
    }
    return chain;
  }
  // The information on x_j with x_i fixed that marginalizing the poses
  // between them out of the linearized chain leaves (a dense Schur
  // complement).
  Eigen::Matrix<double, D, D> Marginal(int i, int j) const {
    std::vector<Pose> x(steps.size() + 1);
    for (size_t k = 0; k < steps.size(); ++k) x[k + 1] = x[k] * steps[k];
    const int m = j - i;
    Eigen::MatrixXd h = Eigen::MatrixXd::Zero(m * D, m * D);
    for (int k = i; k < j; ++k) {
      typename Pose::Jacobian ja, jb;
      EdgeResidualAndJacobians(steps[k], x[k], x[k + 1], &ja, &jb);
      const int a = k - i - 1, b = k - i;
      h.block(b * D, b * D, D, D) += jb.transpose() * information[k] * jb;
      if (a < 0) continue;
      h.block(a * D, a * D, D, D) += ja.transpose() * information[k] * ja;
      h.block(a * D, b * D, D, D) += ja.transpose() * information[k] * jb;
      h.block(b * D, a * D, D, D) += jb.transpose() * information[k] * ja;
    }
    const Eigen::MatrixXd cov = h.inverse();
    return cov.bottomRightCorner(D, D).inverse();
  }
};

template <class Pose>
class OdometryChainTest : public ::testing::Test {};
using Poses = ::testing::Types<Pose2, Pose3>;
TYPED_TEST_SUITE(OdometryChainTest, Poses);

TYPED_TEST(OdometryChainTest, CondensedEdgeIsTheMarginalOfTheStretch) {
  const RandomChain<TypeParam> random(300);
  const OdometryChain<TypeParam> chain = random.Chain();
  // Short stretches are compounded step by step, long ones from prefix sums.
  for (const auto& [i, j] : {std::pair{5, 40}, std::pair{10, 250}}) {
    const auto edge = chain.Between(i, j);
    const auto expected = random.Marginal(i, j);
    EXPECT_LT((edge.information - expected).norm(), 1e-8 * expected.norm())
        << i << " -> " << j;
    TypeParam composed;
    for (int k = i; k < j; ++k) composed = composed * random.steps[k];
    EXPECT_LT(edge.measurement.between(composed).Log().norm(), 1e-9);
  }
}

TYPED_TEST(OdometryChainTest, DirectAndPrefixCompoundingAgree) {
  const RandomChain<TypeParam> random(200);
  const OdometryChain<TypeParam> chain = random.Chain();
  const int n = OdometryChain<TypeParam>::kDirectSteps;
  // The stretch just past the direct limit uses the prefix sums.
  const auto edge = chain.Between(3, 3 + n + 1);
  const auto expected = random.Marginal(3, 3 + n + 1);
  EXPECT_LT((edge.information - expected).norm(), 1e-8 * expected.norm());
}

TEST(OdometryChain, TravelledSumsTheStepsLengthsEitherWay) {
  OdometryChain<Pose2> chain;
  chain.Append(Pose2(3.0, 4.0, 0.5), Pose2::Jacobian::Identity());
  chain.Append(Pose2(0.0, 0.0, 1.0), Pose2::Jacobian::Identity());   // turns
  chain.Append(Pose2(-1.0, 0.0, 0.0), Pose2::Jacobian::Identity());  // back
  EXPECT_DOUBLE_EQ(chain.Travelled(0, 3), 6.0);
  EXPECT_DOUBLE_EQ(chain.Travelled(3, 0), 6.0);
  EXPECT_DOUBLE_EQ(chain.Travelled(1, 2), 0.0);
  EXPECT_DOUBLE_EQ(chain.Travelled(2, 3), 1.0);
  // The way travelled, not the distance between the ends: pose 3 lies
  // within 6 of pose 0 only by the turn.
  EXPECT_LT(chain.Relative(0, 3).translation().norm(), 6.0);
}

TEST(OdometryStepsOf, InvertsBackwardEdgesAndFusesDuplicates) {
  PoseGraph<Pose2> graph;
  for (int k = 0; k < 3; ++k) graph.AddPose(k, Pose2(k, 0, 0));
  const Pose2 step(1.0, 0.2, 0.1);
  Pose2::Jacobian info = Pose2::Jacobian::Identity() * 4.0;
  graph.AddEdge({0, 1, step, info});
  graph.AddEdge({2, 1, step.inverse(), info});  // stored backwards
  graph.AddEdge({1, 2, step, info});            // the same step again
  const std::vector<Constraint<Pose2>> steps = OdometryStepsOf(graph);
  ASSERT_EQ(steps.size(), 2u);
  EXPECT_EQ(steps[1].from, 1);
  EXPECT_EQ(steps[1].to, 2);
  EXPECT_LT(steps[1].measurement.between(step).Log().norm(), 1e-12);
  // Two measurements of one step: their information adds, the backward
  // edge's seen forwards (Ω' = Ad(z)⁻ᵀ Ω Ad(z)⁻¹ with z = step⁻¹).
  const Pose2::Jacobian ad = step.Adjoint();
  const Pose2::Jacobian expected = info + ad.transpose() * info * ad;
  EXPECT_LT((steps[1].information - expected).norm(), 1e-9 * expected.norm());
  EXPECT_EQ(steps[0].information, info);
  // The chain is made of these steps.
  const OdometryChain<Pose2> chain = ChainOf(graph);
  ASSERT_EQ(chain.num_poses(), 3);
  for (int k = 0; k < 2; ++k) {
    const auto between = chain.Between(k, k + 1);
    EXPECT_LT(between.measurement.between(steps[k].measurement).Log().norm(),
              1e-12);
    EXPECT_LT((between.information - steps[k].information).norm(),
              1e-9 * expected.norm());
  }
}

TEST(OdometryStepsOf, MarksThePoseWithoutOdometryAndChainOfNamesIt) {
  PoseGraph<Pose2> graph;
  for (int k = 0; k < 3; ++k) graph.AddPose(k + 10, Pose2());
  graph.AddEdge({0, 1, Pose2(1, 0, 0), Pose2::Jacobian::Identity()});
  const std::vector<Constraint<Pose2>> steps = OdometryStepsOf(graph);
  ASSERT_EQ(steps.size(), 2u);
  EXPECT_EQ(steps[0].from, 0);
  EXPECT_EQ(steps[1].from, -1);  // pose 12 starts a chain
  try {
    ChainOf(graph);
    FAIL() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("pose 12"), std::string::npos);
  }
}

}  // namespace
}  // namespace rrr
