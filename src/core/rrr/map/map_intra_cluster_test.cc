#include "rrr/rrr/map/map_intra_cluster.h"

#include <gtest/gtest.h>

#include <set>

#include "../../testing/noisy_chain.h"
#include "rrr/geometry/pose2.h"
#include "rrr/solver/condensed_solve.h"

namespace rrr {
namespace {

// A revisit of five links: poses 100..104 seen again at 300..304.
PoseGraph<Pose2> Revisit() {
  return testing::NoisyChain<Pose2>(
      400, {{100, 300}, {101, 301}, {102, 302}, {103, 303}, {104, 304}}, 0.01);
}

// Adds loop `k` again as loop 5, its measurement moved `metres` along x.
void AddSpoiledCopy(PoseGraph<Pose2>* graph, int k, double metres) {
  auto loop = graph->loops()[k];
  loop.measurement = loop.measurement * Pose2(metres, 0.0, 0.0);
  graph->AddEdge(loop);
}

// D² of each loop minimized alone with the odometry.
std::vector<double> AloneChi2(const PoseGraph<Pose2>& graph,
                              const OdometryChain<Pose2>& chain) {
  std::vector<double> out;
  for (int k = 0; k < static_cast<int>(graph.loops().size()); ++k) {
    out.push_back(SolveCondensed(graph, chain, {k}, ConvergenceOptions())
                      .errors.total_chi2);
  }
  return out;
}

const ChiSquareQuantile kChi2(0.95);

TEST(MapIntraCluster, KeepsEveryLinkOfATrueRevisit) {
  const PoseGraph<Pose2> graph = Revisit();
  const OdometryChain<Pose2> chain = ChainOf(graph);
  const IntraClusterOutcome outcome =
      MapIntraCluster(graph, chain, {0, 1, 2, 3, 4}, AloneChi2(graph, chain),
                      1.0, kChi2, ConvergenceOptions());
  EXPECT_EQ(outcome.survivors, (std::vector<int>{0, 1, 2, 3, 4}));
  EXPECT_TRUE(outcome.left_out.empty());
  EXPECT_FALSE(outcome.refuted);
  EXPECT_EQ(outcome.solves, 1);
  EXPECT_EQ(outcome.not_converged, 0);
}

TEST(MapIntraCluster, LeavesOutALinkTheOdometryRefutesAlone) {
  PoseGraph<Pose2> graph = Revisit();
  AddSpoiledCopy(&graph, 2, 20.0);
  const OdometryChain<Pose2> chain = ChainOf(graph);
  const std::vector<double> alone = AloneChi2(graph, chain);
  ASSERT_GT(alone[5], kChi2(3));
  const IntraClusterOutcome outcome = MapIntraCluster(
      graph, chain, {0, 1, 5, 3, 4}, alone, 1.0, kChi2, ConvergenceOptions());
  EXPECT_EQ(outcome.survivors, (std::vector<int>{0, 1, 3, 4}));
  EXPECT_TRUE(outcome.left_out.empty());  // refuted, not left out
  EXPECT_TRUE(outcome.refuted);
  EXPECT_EQ(outcome.solves, 1);  // the rest passes at once
}

TEST(MapIntraCluster, DropsTheWorstLinkUntilTheRestIsConsistent) {
  PoseGraph<Pose2> graph = Revisit();
  AddSpoiledCopy(&graph, 4, 1.0);
  const OdometryChain<Pose2> chain = ChainOf(graph);
  // Taken as not refuted alone (as a failed alone solve, -1, is): the
  // greedy must find it.
  const std::vector<double> alone(graph.loops().size(), -1.0);
  const IntraClusterOutcome outcome = MapIntraCluster(
      graph, chain, {0, 1, 2, 3, 5}, alone, 1.0, kChi2, ConvergenceOptions());
  EXPECT_EQ(outcome.survivors, (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(outcome.left_out, (std::vector<int>{5}));
  EXPECT_FALSE(outcome.refuted);
  EXPECT_EQ(outcome.solves, 2);
}

TEST(MapIntraCluster, KeepsOneOfTwoAccountsAndLeavesOutTheOther) {
  // Links 3 and 4 again, both moved 1 m the same way: two accounts of the
  // revisit that each fit the odometry, three links against two.
  PoseGraph<Pose2> graph = Revisit();
  AddSpoiledCopy(&graph, 3, 1.0);
  AddSpoiledCopy(&graph, 4, 1.0);
  const OdometryChain<Pose2> chain = ChainOf(graph);
  const std::vector<double> alone = AloneChi2(graph, chain);
  const IntraClusterOutcome outcome = MapIntraCluster(
      graph, chain, {0, 1, 2, 5, 6}, alone, 1.0, kChi2, ConvergenceOptions());
  // The greedy, dropping the worst link of each compromise, keeps one
  // account (not always the larger) and leaves out the other.
  const std::set<std::vector<int>> accounts{outcome.survivors,
                                            outcome.left_out};
  EXPECT_EQ(accounts, (std::set<std::vector<int>>{{0, 1, 2}, {5, 6}}));
}

TEST(MapIntraCluster, AMajorityThatAgreesLeavesOutTheRevisit) {
  // Three links moved 1 m the same way outnumber the two true ones: the
  // odometry cannot tell which account is right, and the greedy keeps the
  // larger.
  PoseGraph<Pose2> graph = Revisit();
  for (const int k : {2, 3, 4}) AddSpoiledCopy(&graph, k, 1.0);
  const OdometryChain<Pose2> chain = ChainOf(graph);
  const std::vector<double> alone = AloneChi2(graph, chain);
  const IntraClusterOutcome outcome = MapIntraCluster(
      graph, chain, {0, 1, 5, 6, 7}, alone, 1.0, kChi2, ConvergenceOptions());
  EXPECT_EQ(outcome.survivors, (std::vector<int>{5, 6, 7}));
  EXPECT_EQ(outcome.left_out, (std::vector<int>{0, 1}));
}

TEST(MapIntraCluster, AScaleTooSmallForTheNoiseRejectsTheRevisit) {
  const PoseGraph<Pose2> graph = Revisit();
  const OdometryChain<Pose2> chain = ChainOf(graph);
  const IntraClusterOutcome outcome =
      MapIntraCluster(graph, chain, {0, 1, 2, 3, 4}, AloneChi2(graph, chain),
                      1e-6, kChi2, ConvergenceOptions());
  EXPECT_TRUE(outcome.survivors.empty());
  EXPECT_TRUE(outcome.refuted);  // every link is, under that scale
}

}  // namespace
}  // namespace rrr
