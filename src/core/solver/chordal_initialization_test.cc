#include "rrr/solver/chordal_initialization.h"

#include <gtest/gtest.h>

#include "../testing/noisy_chain.h"
#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/io/g2o.h"
#include "rrr/sim/simulated_world.h"
#include "rrr/solver/pose_graph_solver.h"

namespace rrr {
namespace {

template <class Pose>
class ChordalInitializationTest : public ::testing::Test {};
using PoseTypes = ::testing::Types<Pose2, Pose3>;
TYPED_TEST_SUITE(ChordalInitializationTest, PoseTypes);

TYPED_TEST(ChordalInitializationTest, ExactMeasurementsGiveTheTruth) {
  // Noise-free edges agree with one set of poses; the relaxation is exact.
  const auto graph =
      testing::NoisyChain<TypeParam>(60, {{5, 40}, {10, 55}, {0, 30}}, 1e-12);
  const std::vector<TypeParam> x = ChordalInitialization(graph, {0, 1, 2});
  ASSERT_EQ(x.size(), 60u);
  for (int p = 0; p < 60; ++p) {
    EXPECT_LT(graph.estimates()[p].between(x[p]).Log().norm(), 1e-6) << p;
  }
}

TEST(ChordalInitialization, StartsCloserThanTheOdometryWhereLoopsCloseDrift) {
  // A grid city with noisy odometry: composing the odometry drifts, while
  // the relaxation spreads each loop's correction; the error of every edge
  // at its start is far lower, and the minimum from it is no worse.
  WorldOptions options;
  options.poses = 1500;
  options.false_loops = 0;
  options.rotation_noise = 0.02;
  const SimulatedWorld w = SimulateWorld(options);
  const std::vector<int> all = AllLoops(w.graph);
  const std::vector<Pose2> chordal = ChordalInitialization(w.graph, all);
  PoseGraphSolver<Pose2> solver(w.graph, 1);
  const double from_odometry =
      solver.Evaluate(all, solver.initial()).total_chi2;
  const double from_chordal = solver.Evaluate(all, chordal).total_chi2;
  EXPECT_LT(from_chordal, 0.1 * from_odometry);
  MinimizeResult odometry_min, chordal_min;
  solver.Optimize(all, ConvergenceOptions{1000, 1e-9}, &odometry_min);
  solver.Optimize(all, ConvergenceOptions{1000, 1e-9}, &chordal_min, &chordal);
  EXPECT_TRUE(chordal_min.converged);
  EXPECT_LE(chordal_min.final_chi2, odometry_min.final_chi2 * (1 + 1e-6));
}

TEST(ChordalInitialization, RefusesPosesThatNoEdgeReaches) {
  PoseGraph<Pose2> graph;
  graph.AddPose(0, Pose2());
  graph.AddPose(1, Pose2(1, 0, 0));
  graph.AddPose(5, Pose2(2, 0, 0));  // no odometry to it
  graph.AddEdge(
      {0, 1, Pose2(1, 0, 0), Constraint<Pose2>::Information::Identity()});
  EXPECT_THROW(ChordalInitialization(graph, {}), std::runtime_error);
}

}  // namespace
}  // namespace rrr
