// The decision procedure on a scripted solver whose answers are known.
#include "rrr/rrr/consistency_tests.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>

namespace rrr {
namespace {

// Every loop belongs to a "world" (a hypothesis about the map). A solve
// agrees with the world holding most active loops (ties: the lower world):
// its loops end with error 1, every other loop with error 100, and each of
// those adds `odometry_penalty` to the odometry error. 100 odometry edges.
class ScriptedSolver : public ConsistencySolver {
 public:
  ScriptedSolver(std::vector<int> world_of_loop, double odometry_penalty)
      : world_(std::move(world_of_loop)), penalty_(odometry_penalty) {}

  SubsetErrors Solve(const std::vector<int>& active) override {
    ++solves;
    std::map<int, int> count;
    for (const int l : active) ++count[world_[l]];
    int winner = -1, most = 0;
    for (const auto& [w, n] : count) {
      if (n > most) winner = w, most = n;
    }
    SubsetErrors out;
    out.num_edges = 100 + static_cast<int>(active.size());
    for (const int l : active) {
      const bool agrees = world_[l] == winner;
      out.loop_chi2.push_back(agrees ? 1.0 : 100.0);
      out.total_chi2 += out.loop_chi2.back() + (agrees ? 0.0 : penalty_);
    }
    return out;
  }
  int residual_dim() const override { return 3; }
  int solves = 0;

 private:
  std::vector<int> world_;
  double penalty_;
};

const ChiSquareQuantile kChi2(0.95);

TEST(IntraClusterConsistent, DropsTheOutlierLinkOfAConsistentCluster) {
  ScriptedSolver solver({1, 1, 2, 1}, /*odometry_penalty=*/0.0);
  EXPECT_EQ(IntraClusterConsistent({0, 1, 2, 3}, solver, kChi2),
            (std::vector<int>{0, 1, 3}));
}

TEST(IntraClusterConsistent, RejectsAClusterThatBendsOdometry) {
  ScriptedSolver solver({1, 1, 2, 1}, /*odometry_penalty=*/1000.0);
  EXPECT_TRUE(IntraClusterConsistent({0, 1, 2, 3}, solver, kChi2).empty());
}

TEST(IntraClusterConsistent, KeepsAFullyConsistentCluster) {
  ScriptedSolver solver({4, 4}, 1000.0);
  EXPECT_EQ(IntraClusterConsistent({0, 1}, solver, kChi2),
            (std::vector<int>{0, 1}));
}

TEST(InterClusterConsistent, AcceptsTheAgreeingMajorityAndRejectsTheRest) {
  // Clusters: {0,1,2} and {3,4} in world 1, {5} in world 2.
  ScriptedSolver solver({1, 1, 1, 1, 1, 2}, 0.0);
  const auto good =
      InterClusterConsistent({{0, 1, 2}, {3, 4}, {5}}, solver, kChi2);
  EXPECT_EQ(good, (std::vector<bool>{true, true, false}));
}

TEST(InterClusterConsistent, DropsTheLeastConsistentClusterUntilTheRestAgree) {
  // Cluster {3, 4} mixes worlds: link 3 agrees, so it passes the filter of
  // step 2, but link 4 makes the joint test fail; it has the largest CI, is
  // set aside, and the rest pass. Alone later, it still fails with good.
  ScriptedSolver solver({1, 1, 1, 1, 2}, 0.0);
  const auto good =
      InterClusterConsistent({{0, 1}, {2}, {3, 4}}, solver, kChi2);
  EXPECT_EQ(good, (std::vector<bool>{true, true, false}));
}

TEST(InterClusterConsistent, RejectedClustersGetAnotherChanceAfterGoodGrows) {
  // Round 1: H = all; world 2 (4 loops) outvotes world 1, so cluster A is
  // filtered out and {B, C} are accepted. Round 2: A alone agrees with
  // itself, but not jointly with good, so it ends rejected.
  ScriptedSolver solver({1, 1, 1, 2, 2, 2, 2}, 0.0);
  const auto good =
      InterClusterConsistent({{0, 1, 2}, {3, 4}, {5, 6}}, solver, kChi2);
  EXPECT_EQ(good, (std::vector<bool>{false, true, true}));
}

TEST(InterClusterConsistent, NoClustersNoSolves) {
  ScriptedSolver solver({}, 0.0);
  EXPECT_TRUE(InterClusterConsistent({}, solver, kChi2).empty());
  EXPECT_EQ(solver.solves, 0);
}

TEST(InterClusterConsistent, StopsWhenNoLinkIsJointlyConsistent) {
  // Two worlds of equal size: the lower one wins the vote, and the other one
  // is set aside; nothing is lost from the winner.
  ScriptedSolver solver({1, 2}, 0.0);
  EXPECT_EQ(InterClusterConsistent({{0}, {1}}, solver, kChi2),
            (std::vector<bool>{true, false}));
}

TEST(TotalErrorConsistent, SpanGateCountsOnlyTheSpannedEdges) {
  // A loop bends 10 edges of a 1000-edge graph by a total error of 100:
  // the whole-graph gate χ²(3000) lets it pass, the span gate χ²(30) does not.
  SubsetErrors errors;
  errors.total_chi2 = 100.0;
  errors.num_edges = 1000;
  errors.num_spanned_edges = 10;
  EXPECT_TRUE(TotalErrorConsistent(errors, 3, kChi2, /*span_gate=*/false));
  EXPECT_FALSE(TotalErrorConsistent(errors, 3, kChi2, /*span_gate=*/true));
  errors.total_chi2 = 20.0;
  EXPECT_TRUE(TotalErrorConsistent(errors, 3, kChi2, /*span_gate=*/true));
}

TEST(ChiSquareQuantile, MatchesTables) {
  EXPECT_NEAR(kChi2(1), 3.841, 1e-3);
  EXPECT_NEAR(kChi2(3), 7.815, 1e-3);
  EXPECT_NEAR(ChiSquareQuantile(0.99)(6), 16.812, 1e-3);
  EXPECT_THROW(ChiSquareQuantile(1.0), std::invalid_argument);
  EXPECT_THROW(kChi2(0), std::invalid_argument);
}

}  // namespace
}  // namespace rrr
