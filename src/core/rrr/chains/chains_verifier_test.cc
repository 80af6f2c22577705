#include "rrr/rrr/chains/chains_verifier.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <map>
#include <stdexcept>
#include <tuple>
#include <vector>

#include "../../testing/chain_worlds.h"
#include "rrr/geometry/pose2.h"
#include "rrr/graph/candidate_defect.h"
#include "rrr/rrr/chains/verify_chains.h"

namespace rrr {
namespace {

using testing::AppendChain;
using testing::ChainWorldOptions;
using testing::Grid;
using testing::JudgedAlone;
using testing::SessionsWithAFalseRevisit;
using testing::ThreeSessionsWithAFalseJoin;
using testing::TwoSessionsWithFalseLoops;

using Changes = std::vector<DecisionChange>;

// The pose of `graph` at index `p` as a pose of its chain.
ChainPose At(const PoseGraph<Pose2>& graph, const std::vector<ChainSpan>& spans,
             int p) {
  return {ChainHolding(spans, p), graph.ids()[p]};
}

// The candidates `verifier` accepted, ascending.
std::vector<int> Accepted(const ChainsVerifier<Pose2>& verifier) {
  std::vector<int> accepted;
  for (int c = 0; c < verifier.num_candidates(); ++c) {
    if (verifier.state(c) == LoopState::kAccepted) accepted.push_back(c);
  }
  return accepted;
}

// The candidates VerifyChains accepts on the verifier's graph, ascending.
std::vector<int> AcceptedByVerifyChains(const ChainsVerifier<Pose2>& verifier) {
  std::vector<int> candidate_of_loop;
  const PoseGraph<Pose2> graph = verifier.Graph(&candidate_of_loop);
  std::vector<int> accepted;
  for (const int k :
       VerifyChains(graph, ChainWorldOptions()).verdict.accepted) {
    accepted.push_back(candidate_of_loop[k]);
  }
  std::sort(accepted.begin(), accepted.end());
  return accepted;
}

TEST(ChainsVerifier, TwoRobotsSideBySideAreJoinedAsVerifyChainsJoinsThem) {
  // One world walked by two robots at once, the second starting where the
  // first's pose 500 is (its odometry from zero), with 200 false loops
  // between them.
  const SimulatedWorld world = SimulateWorld(Grid(1000, 2));
  size_t true_loops = 0;
  const PoseGraph<Pose2> two =
      TwoSessionsWithFalseLoops(world, 500, &true_loops);
  ChainsVerifier<Pose2> verifier(ChainWorldOptions());
  const std::vector<int> candidate_of_loop = FeedSideBySide(two, &verifier, 10);
  verifier.Finish();

  ASSERT_EQ(verifier.num_chains(), 2);
  EXPECT_EQ(verifier.map_of_chain(1), 0);
  EXPECT_EQ(verifier.num_in_state(LoopState::kPending), 0);
  EXPECT_EQ(Accepted(verifier), AcceptedByVerifyChains(verifier));
  int true_accepted = 0;
  for (size_t loop = 0; loop < candidate_of_loop.size(); ++loop) {
    const int candidate = candidate_of_loop[loop];
    if (candidate < 0) continue;
    const bool accepted = verifier.state(candidate) == LoopState::kAccepted;
    if (loop >= true_loops) {
      EXPECT_FALSE(accepted) << "false loop " << loop;
    }
    true_accepted += accepted;
  }
  EXPECT_GE(true_accepted, 0.95 * static_cast<double>(true_loops));
  // Its graph has no odometry between the robots.
  const PoseGraph<Pose2> graph = verifier.Graph();
  EXPECT_EQ(ChainSpansOf(graph).size(), 2u);
  // The second robot placed where it started, relative to the first.
  const Pose2 start = verifier.Map(0)[0].between(verifier.Map(1)[0]);
  const Pose2 truth = world.truth[0].between(world.truth[500]);
  EXPECT_LT((start.translation() - truth.translation()).norm(), 1.0);
}

TEST(ChainsVerifier, AJoinIsReversedWhenStrongerJoinsContradictIt) {
  // Three sessions; first only the loops between the first two come, among
  // them two false revisits that agree on one wrong placement: they join
  // the two. Then the true loops of the third with each come: those joins,
  // on more evidence, put all three in one map that refutes the first join,
  // and its loops change from accepted to refused.
  const SimulatedWorld world = SimulateWorld(Grid(1500, 3));
  const std::vector<int> cuts = {500, 1000};
  size_t true_loops = 0;
  const PoseGraph<Pose2> three =
      ThreeSessionsWithAFalseJoin(world, cuts, &true_loops);
  const std::vector<ChainSpan> spans = ChainSpansOf(three);
  std::vector<int> first, later;
  for (size_t k = 0; k < three.loops().size(); ++k) {
    const auto& e = three.loops()[k];
    const int a = ChainHolding(spans, e.from), b = ChainHolding(spans, e.to);
    (a == b || std::max(a, b) < 2 ? first : later)
        .push_back(static_cast<int>(k));
  }
  ChainsVerifier<Pose2> verifier(ChainWorldOptions());
  std::vector<int> candidate_of_loop =
      FeedSideBySide(three, &verifier, 10, first);
  verifier.Update();
  ASSERT_EQ(verifier.map_of_chain(1), 0) << "the false join to reverse";
  std::vector<int> falsely_accepted;
  for (size_t loop = 0; loop < candidate_of_loop.size(); ++loop) {
    const int candidate = candidate_of_loop[loop];
    if (candidate < 0) continue;
    if (loop >= true_loops &&
        verifier.state(candidate) == LoopState::kAccepted) {
      falsely_accepted.push_back(candidate);
    }
  }
  ASSERT_FALSE(falsely_accepted.empty());

  // The later loops, as candidates that name poses that exist.
  for (const int k : later) {
    const auto& e = three.loops()[k];
    candidate_of_loop[k] =
        verifier.AddLoop(At(three, spans, e.from), At(three, spans, e.to),
                         e.measurement, e.information);
  }
  const Changes changes = verifier.Update();
  for (const int candidate : falsely_accepted) {
    EXPECT_EQ(verifier.state(candidate), LoopState::kRejected);
    const auto change = std::find_if(
        changes.begin(), changes.end(),
        [&](const DecisionChange& c) { return c.candidate == candidate; });
    ASSERT_NE(change, changes.end()) << "candidate " << candidate;
    EXPECT_EQ(change->previous, LoopState::kAccepted);
  }
  EXPECT_EQ(verifier.map_of_chain(2), 0);
  verifier.Finish();
  for (size_t loop = 0; loop < candidate_of_loop.size(); ++loop) {
    const int candidate = candidate_of_loop[loop];
    if (candidate < 0) continue;
    if (loop >= true_loops) {
      EXPECT_NE(verifier.state(candidate), LoopState::kAccepted) << loop;
    }
  }
  EXPECT_EQ(Accepted(verifier), AcceptedByVerifyChains(verifier));
}

TEST(ChainsVerifier, LoopsBetweenRobotsNeverJoinedWaitUntilFinishRefusesThem) {
  // Two robots in two different worlds, 100 false loops between them.
  PoseGraph<Pose2> apart;
  AppendChain(SimulateWorld(Grid(400, 5)), Pose2(), &apart);
  AppendChain(SimulateWorld(Grid(400, 6)), Pose2(3.0, 1.0, 0.5), &apart);
  const size_t true_loops = apart.loops().size();
  FalseLoopOptions spoil;
  spoil.count = 100;
  spoil.between_chains = true;
  spoil.seed = 7;
  AddFalseLoops(&apart, spoil);
  ChainsVerifier<Pose2> verifier(ChainWorldOptions());
  const std::vector<int> candidate_of_loop =
      FeedSideBySide(apart, &verifier, 10);
  // During the run: a loop a cluster's own links refute is refused, the
  // others wait, since nothing can confirm them.
  int waiting = 0;
  for (size_t loop = 0; loop < candidate_of_loop.size(); ++loop) {
    const int candidate = candidate_of_loop[loop];
    if (candidate < 0) continue;
    if (loop < true_loops) continue;
    const DecisionTest test = verifier.reason(candidate).test;
    if (verifier.state(candidate) == LoopState::kPending) {
      EXPECT_EQ(test, DecisionTest::kApart) << ToString(test);
      ++waiting;
    } else {
      EXPECT_EQ(verifier.state(candidate), LoopState::kRejected) << loop;
      EXPECT_TRUE(test == DecisionTest::kOwn || test == DecisionTest::kOwnLink)
          << ToString(test);
    }
  }
  EXPECT_GT(waiting, 50);
  verifier.Finish();
  EXPECT_EQ(verifier.map_of_chain(1), 1);
  for (size_t loop = 0; loop < candidate_of_loop.size(); ++loop) {
    const int candidate = candidate_of_loop[loop];
    if (candidate < 0) continue;
    if (loop < true_loops) continue;
    EXPECT_EQ(verifier.state(candidate), LoopState::kRejected) << loop;
  }
  EXPECT_EQ(Accepted(verifier), AcceptedByVerifyChains(verifier));
}

TEST(ChainsVerifier, InTheBackgroundItDecidesAtFinishAsAtOnce) {
  // The three sessions, every loop in arrival order, rules 1–3 on a thread
  // of their own: the decisions at Finish() are VerifyChains' all the same.
  const SimulatedWorld world = SimulateWorld(Grid(1500, 3));
  size_t true_loops = 0;
  const PoseGraph<Pose2> three =
      ThreeSessionsWithAFalseJoin(world, {500, 1000}, &true_loops);
  ChainsVerifier<Pose2> verifier(ChainWorldOptions(), true);
  const std::vector<int> candidate_of_loop =
      FeedSideBySide(three, &verifier, 1);
  verifier.Finish();
  EXPECT_EQ(verifier.num_in_state(LoopState::kPending), 0);
  EXPECT_EQ(Accepted(verifier), AcceptedByVerifyChains(verifier));
  EXPECT_EQ(verifier.map_of_chain(1), 0);
  EXPECT_EQ(verifier.map_of_chain(2), 0);
  for (size_t loop = true_loops; loop < candidate_of_loop.size(); ++loop) {
    EXPECT_NE(verifier.state(candidate_of_loop[loop]), LoopState::kAccepted);
  }
}

TEST(ChainsVerifier, ARobotsFalseRevisitIsRefusedOnceTheJoinedMapRefutesIt) {
  // The second robot's own verifier accepts a false revisit that its drift
  // explains, and later refuses true loops against the map it bent; once
  // the robots are joined, rule 5 refutes the revisit and the fleet's
  // decisions stand in for the robot's, before Finish() and after.
  const SimulatedWorld world = SimulateWorld(Grid(2400, 4));
  size_t true_loops = 0;
  const PoseGraph<Pose2> two =
      SessionsWithAFalseRevisit(world, {800}, &true_loops);
  // The true loops inside the second robot that it refuses alone.
  std::vector<int> inside;
  const Verdict alone = JudgedAlone(two, ChainSpansOf(two)[1], &inside);
  std::vector<size_t> refused_alone;
  for (const int k : alone.rejected) {
    if (static_cast<size_t>(inside[k]) < true_loops) {
      refused_alone.push_back(inside[k]);
    }
  }
  ASSERT_FALSE(refused_alone.empty());

  ChainsVerifier<Pose2> verifier(ChainWorldOptions());
  // Per candidate: accepted at some update, then refused by rule 5.
  std::map<int, std::pair<bool, bool>> seen;
  const auto watch = [&](const Changes& changes) {
    for (const DecisionChange& change : changes) {
      auto& [accepted, refuted] = seen[change.candidate];
      accepted = accepted || change.current == LoopState::kAccepted;
      refuted =
          refuted ||
          (accepted && change.current == LoopState::kRejected &&
           verifier.reason(change.candidate).test == DecisionTest::kJoinedMap);
    }
  };
  const std::vector<int> candidate_of_loop =
      FeedSideBySide(two, &verifier, 50, {}, watch);
  int refuted_online = 0;
  for (size_t loop = true_loops; loop < two.loops().size(); ++loop) {
    const auto& [accepted, refuted] = seen[candidate_of_loop[loop]];
    refuted_online += accepted && refuted;
  }
  EXPECT_GT(refuted_online, 0);
  int kept_online = 0;
  for (const size_t loop : refused_alone) {
    kept_online += seen[candidate_of_loop[loop]].first;
  }
  EXPECT_GT(kept_online, 0) << "of " << refused_alone.size();
  verifier.Finish();
  EXPECT_EQ(Accepted(verifier), AcceptedByVerifyChains(verifier));
  int refuted_at_finish = 0;
  for (size_t loop = true_loops; loop < two.loops().size(); ++loop) {
    const int candidate = candidate_of_loop[loop];
    EXPECT_EQ(verifier.state(candidate), LoopState::kRejected);
    refuted_at_finish +=
        verifier.reason(candidate).test == DecisionTest::kJoinedMap;
  }
  EXPECT_GT(refuted_at_finish, 0);
}

TEST(ChainsVerifier, CandidatesBetweenChainsWaitForTheirPosesOrAreRefused) {
  ChainsVerifier<Pose2> verifier(ChainWorldOptions());
  const Eigen::Matrix3d information = Eigen::Matrix3d::Identity();
  verifier.AddChain(0, Pose2());
  verifier.AddChain(100, Pose2(5.0, 0.0, 0.0));
  for (int k = 0; k < 5; ++k) {
    verifier.AddOdometry(0, Pose2(1.0, 0.0, 0.0), information);
  }
  const Pose2 z(2.0, 0.0, 0.0);
  const int waits = verifier.AddLoop({0, 3}, {1, 102}, z, information);
  EXPECT_EQ(verifier.Graph().loops().size(), 0u) << "pose 102 not there";
  verifier.AddOdometry(1, Pose2(1.0, 0.0, 0.0), information);
  verifier.AddOdometry(1, Pose2(1.0, 0.0, 0.0), information);
  EXPECT_EQ(verifier.Graph().loops().size(), 1u);
  EXPECT_EQ(verifier.state(waits), LoopState::kPending);

  const auto defect = [&](ChainPose a, ChainPose b) {
    try {
      verifier.AddLoop(a, b, z, information);
    } catch (const DegenerateCandidate& e) {
      return e.defect();
    }
    ADD_FAILURE() << "accepted as a candidate";
    return CandidateDefect::kSelfLoop;
  };
  EXPECT_EQ(defect({0, 3}, {1, 102}), CandidateDefect::kDuplicate);
  EXPECT_EQ(defect({0, 3}, {1, 99}), CandidateDefect::kUnknownPose);
  EXPECT_EQ(defect({0, 3}, {1, 5000}), CandidateDefect::kTooFarAhead);
  EXPECT_EQ(defect({0, 2}, {0, 3}), CandidateDefect::kConsecutivePoses);
  EXPECT_THROW(verifier.AddLoop({0, 3}, {2, 0}, z, information),
               std::out_of_range);
  EXPECT_THROW(verifier.AddOdometry(2, z, information), std::out_of_range);
  EXPECT_EQ(verifier.num_candidates(), 1);
}

}  // namespace
}  // namespace rrr
