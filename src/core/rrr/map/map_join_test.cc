// The join rule of the map procedure: which maps of odometry chains loops
// between them join, stated as outcomes.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "../../testing/chain_worlds.h"
#include "rrr/rrr/map/map_verifier.h"
#include "rrr/rrr/map/verify_with_map.h"

namespace rrr {
namespace {

// A ring of 200 poses driven 350 poses, cut at pose 150: the second chain
// drives on from three quarters of the first lap and, from pose 200 on,
// revisits the whole first chain (one long revisit, in pieces the
// clustering cuts).
PoseGraph<Pose2> RingInTwo() {
  WorldOptions world;
  world.layout = Layout::kRing;
  world.poses = 350;
  world.ring = 200;
  world.false_loops = 0;
  world.seed = 7;
  return testing::CutAt(SimulateWorld(world).graph, {150});
}

// The decisions of the map procedure on `graph`, its chains one after the
// other; `*between` receives the loops between chains.
Verdict Judged(const PoseGraph<Pose2>& graph, std::vector<int>* between,
               MapVerifierStats* stats = nullptr) {
  const std::vector<ChainSpan> spans = ChainSpansOf(graph);
  between->clear();
  for (size_t k = 0; k < graph.loops().size(); ++k) {
    const auto& e = graph.loops()[k];
    if (ChainHolding(spans, e.from) != ChainHolding(spans, e.to)) {
      between->push_back(static_cast<int>(k));
    }
  }
  return VerifyWithMap<Pose2>(graph, testing::ChainWorldOptions(), nullptr,
                              stats);
}

bool Accepted(const Verdict& verdict, int loop) {
  return std::binary_search(verdict.accepted.begin(), verdict.accepted.end(),
                            loop);
}

TEST(JoinRule, ALongSingleRevisitJoinsTheChains) {
  const PoseGraph<Pose2> graph = RingInTwo();
  std::vector<int> between;
  MapVerifierStats stats;
  const Verdict verdict = Judged(graph, &between, &stats);
  ASSERT_GE(between.size(), 30u);
  int kept = 0;
  for (const int k : between) kept += Accepted(verdict, k);
  EXPECT_GE(kept, 0.95 * between.size());
  EXPECT_EQ(stats.joins, 1);
}

TEST(JoinRule, LookAlikeGroupsBetweenChainsThatNeverMeetJoinNothing) {
  // Two grid cities far apart, and twenty look-alike groups of five links
  // between them: each agrees with itself, none with another.
  PoseGraph<Pose2> graph;
  testing::AppendChain(SimulateWorld(testing::Grid(600, 1)), Pose2(), &graph);
  testing::AppendChain(SimulateWorld(testing::Grid(600, 2)),
                       Pose2(5000.0, 0.0, 1.0), &graph);
  FalseLoopOptions spoil;
  spoil.count = 100;
  spoil.group = 5;
  spoil.look_alike = true;
  spoil.between_chains = true;
  spoil.seed = 5;
  AddFalseLoops(&graph, spoil);
  std::vector<int> between;
  const Verdict verdict = Judged(graph, &between);
  ASSERT_EQ(between.size(), 100u);
  for (const int k : between) {
    EXPECT_FALSE(Accepted(verdict, k)) << "loop " << k;
    EXPECT_EQ(verdict.reasons[k].test == DecisionTest::kApart ||
                  verdict.reasons[k].test == DecisionTest::kOwn ||
                  verdict.reasons[k].test == DecisionTest::kOwnLink,
              true)
        << "loop " << k << ": " << ToString(verdict.reasons[k].test);
  }
}

TEST(JoinRule, AJoinGivesWayToAStrongerRevisitThatContradictsIt) {
  PoseGraph<Pose2> graph = RingInTwo();
  const size_t true_loops = graph.loops().size();
  // A false revisit of six links before the true one: second-chain poses
  // 160.. seen as first-chain poses 60.., 5 m off their true relation.
  for (int k = 0; k < 6; ++k) {
    Constraint<Pose2> e = graph.loops().front();
    e.from = 60 + k;
    e.to = 160 + k;
    e.measurement = graph.estimates()[e.from].between(graph.estimates()[e.to]);
    // The estimates are each chain's odometry: the first chain's relation
    // to the second is what the false revisit claims.
    e.measurement = Pose2(5.0, 2.0, 0.3) * e.measurement;
    graph.AddEdge(e);
  }
  MapVerifier<Pose2> verifier(testing::ChainWorldOptions());
  bool joined_falsely = false;
  const std::vector<int> loop_of = FeedInArrivalOrder<Pose2>(
      graph, &verifier, 1, [&](const std::vector<DecisionChange>&) {
        for (int c = 0; c < verifier.num_candidates(); ++c) {
          const int loop = verifier.loop_of(c);
          joined_falsely |= loop >= static_cast<int>(true_loops) &&
                            verifier.state(c) == LoopState::kAccepted;
        }
      });
  EXPECT_TRUE(joined_falsely);  // alone, the false revisit joined them
  EXPECT_GE(verifier.stats().join_revisions, 1);
  int true_kept = 0, false_kept = 0;
  for (int c = 0; c < verifier.num_candidates(); ++c) {
    const bool accepted = verifier.state(c) == LoopState::kAccepted;
    (loop_of[c] >= static_cast<int>(true_loops) ? false_kept : true_kept) +=
        accepted;
  }
  EXPECT_EQ(false_kept, 0);
  EXPECT_GE(true_kept, 0.95 * true_loops);
}

TEST(JoinRule, DecisionsAfterEveryUpdateAreThoseOfTheInputsSoFar) {
  PoseGraph<Pose2> graph = RingInTwo();
  FalseLoopOptions spoil;
  spoil.count = 60;
  spoil.group = 3;
  spoil.between_chains = true;
  spoil.seed = 9;
  AddFalseLoops(&graph, spoil);
  // Robots side by side, updated every third pose: at every 30th pose the
  // decisions equal those of a verifier given the same inputs with an
  // update after every pose.
  const std::vector<int> order = ArrivalOrder(graph, true);
  MapVerifier<Pose2> verifier(testing::ChainWorldOptions());
  int compared = 0;
  const auto compare = [&] {
    const int poses = verifier.graph().num_poses();
    if (poses % 30 != 0) return;
    MapVerifier<Pose2> fresh(testing::ChainWorldOptions());
    FeedInArrivalOrder<Pose2>(graph, &fresh, 1, nullptr, 0,
                              {order.begin(), order.begin() + poses}, false);
    ASSERT_EQ(fresh.num_candidates(), verifier.num_candidates());
    for (int c = 0; c < verifier.num_candidates(); ++c) {
      EXPECT_EQ(fresh.state(c), verifier.state(c))
          << "candidate " << c << " after " << poses << " poses";
    }
    ++compared;
  };
  const std::vector<int> loop_of = FeedInArrivalOrder<Pose2>(
      graph, &verifier, 3,
      [&](const std::vector<DecisionChange>&) { compare(); }, 0, order, false);
  EXPECT_GE(compared, 10);
  // After Finish(), the decisions of rrr verify on the whole graph.
  verifier.Finish();
  const Verdict batch = VerifyWithMap<Pose2>(
      graph, testing::ChainWorldOptions(), nullptr, nullptr, order);
  std::vector<int> accepted;
  for (int c = 0; c < verifier.num_candidates(); ++c) {
    if (verifier.state(c) == LoopState::kAccepted) {
      accepted.push_back(loop_of[c]);
    }
  }
  std::sort(accepted.begin(), accepted.end());
  EXPECT_EQ(accepted, batch.accepted);
  EXPECT_GT(batch.accepted.size(), 0u);
}

}  // namespace
}  // namespace rrr
