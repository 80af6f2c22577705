#include "rrr/solver/condensed_solve.h"

#include <gtest/gtest.h>

#include "../testing/noisy_chain.h"
#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/solver/pose_graph_solver.h"

namespace rrr {
namespace {

template <class Pose>
class CondensedSolveTest : public ::testing::Test {};
using Poses = ::testing::Types<Pose2, Pose3>;
TYPED_TEST_SUITE(CondensedSolveTest, Poses);

TYPED_TEST(CondensedSolveTest, MatchesTheWholeChainSolvedToConvergence) {
  const auto graph = testing::NoisyChain<TypeParam>(
      400, {{20, 300}, {22, 302}, {25, 306}, {100, 110}}, 0.01);
  const ChainOdometry<TypeParam> chain = ChainOdometryOf(graph);
  const std::vector<int> loops = {0, 1, 2, 3};
  const CondensedErrors condensed =
      SolveCondensed(graph, chain, loops, ConvergenceOptions());
  EXPECT_TRUE(condensed.minimize.converged);
  // The whole chain, every pose a variable, 30 Gauss–Newton iterations.
  PoseGraphSolver<TypeParam> whole(graph, 30);
  const SubsetErrors full = whole.Solve(loops);
  // Exact for a linear chain; here the condensed edges are first-order.
  EXPECT_NEAR(condensed.errors.total_chi2, full.total_chi2,
              0.03 * full.total_chi2);
  ASSERT_EQ(condensed.errors.loop_chi2.size(), loops.size());
  for (size_t k = 0; k < loops.size(); ++k) {
    EXPECT_NEAR(condensed.errors.loop_chi2[k], full.loop_chi2[k],
                0.03 * full.total_chi2);
  }
  // The condensed problem: 8 touched poses, 7 chain edges and 4 loops.
  EXPECT_EQ(condensed.errors.num_edges, 11);
}

TEST(CondensedSolve, AFalseLoopShowsAsALargeError) {
  auto graph = testing::NoisyChain<Pose2>(200, {{10, 40}}, 0.01);
  const ChainOdometry<Pose2> chain = ChainOdometryOf(graph);
  const double good =
      SolveCondensed(graph, chain, {0}, ConvergenceOptions()).errors.total_chi2;
  auto bad = graph.loops()[0];
  bad.measurement = bad.measurement * Pose2(3.0, 0.0, 0.0);  // 3 m off
  graph.AddEdge(bad);
  const double wrong =
      SolveCondensed(graph, chain, {1}, ConvergenceOptions()).errors.total_chi2;
  EXPECT_LT(good, 20.0);
  EXPECT_GT(wrong, 100.0 * good);
}

}  // namespace
}  // namespace rrr
