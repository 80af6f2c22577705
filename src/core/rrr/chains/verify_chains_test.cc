#include "rrr/rrr/chains/verify_chains.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "../../testing/chain_worlds.h"
#include "rrr/geometry/pose2.h"
#include "rrr/rrr/map/verify_with_map.h"
#include "rrr/sim/false_loops.h"
#include "rrr/sim/simulated_world.h"
#include "rrr/solver/pose_graph_solver.h"

namespace rrr {
namespace {

using testing::AppendChain;
using testing::ChainWorldOptions;
using testing::CutAt;
using testing::Grid;
using testing::JudgedAlone;
using testing::SessionsWithAFalseRevisit;
using testing::ThreeSessionsWithAFalseJoin;
using testing::TwoSessionsWithFalseLoops;

// The loops of `two` between its poses before `cut` and after, in runs of
// consecutive revisits (ends at most two poses from the last link's).
std::vector<std::vector<int>> RunsBetween(const PoseGraph<Pose2>& two,
                                          int cut) {
  std::vector<std::vector<int>> runs;
  for (size_t k = 0; k < two.loops().size(); ++k) {
    const auto& e = two.loops()[k];
    if ((e.from < cut) == (e.to < cut)) continue;
    const bool continues =
        !runs.empty() &&
        std::abs(e.from - two.loops()[runs.back().back()].from) <= 2 &&
        std::abs(e.to - two.loops()[runs.back().back()].to) <= 2;
    if (!continues) runs.emplace_back();
    runs.back().push_back(static_cast<int>(k));
  }
  return runs;
}

// VerifyChains on `two`, two sessions, with the loops `falses` added:
// expects the sessions joined, every loop of `revisit` accepted and every
// one of `falses` refused; returns the reasons of `falses`.
std::vector<DecisionReason> RevisitKeptFalseRefused(
    PoseGraph<Pose2> two, const std::vector<int>& revisit,
    const std::vector<Constraint<Pose2>>& falses) {
  const size_t true_loops = two.loops().size();
  for (const Constraint<Pose2>& e : falses) two.AddEdge(e);
  const ChainsVerdict<Pose2> v = VerifyChains(two, ChainWorldOptions());
  EXPECT_EQ(v.pairs.size(), 1u);
  EXPECT_TRUE(!v.pairs.empty() && v.pairs[0].joined);
  const std::set<int> accepted(v.verdict.accepted.begin(),
                               v.verdict.accepted.end());
  for (const int k : revisit) EXPECT_EQ(accepted.count(k), 1u) << k;
  std::vector<DecisionReason> reasons;
  for (size_t k = true_loops; k < two.loops().size(); ++k) {
    EXPECT_EQ(accepted.count(static_cast<int>(k)), 0u) << k;
    reasons.push_back(v.verdict.reasons[k]);
  }
  return reasons;
}

// For each loop of `revisit`, a copy per shift of its first end by
// `shifts` poses, measuring the truth with the second end moved by `wrong`:
// false links that agree with each other exactly.
std::vector<Constraint<Pose2>> CopiesMovedBy(const PoseGraph<Pose2>& two,
                                             const std::vector<Pose2>& truth,
                                             const std::vector<int>& revisit,
                                             const Pose2& wrong,
                                             const std::vector<int>& shifts) {
  std::vector<Constraint<Pose2>> copies;
  for (const int k : revisit) {
    for (const int shift : shifts) {
      Constraint<Pose2> e = two.loops()[k];
      const int first = std::min(e.from, e.to) + shift;
      const int second = std::max(e.from, e.to);
      e.from = first;
      e.to = second;
      e.measurement = truth[first].between(wrong * truth[second]);
      copies.push_back(e);
    }
  }
  return copies;
}

TEST(ChainSpans, AGapStartsAChain) {
  const SimulatedWorld world = SimulateWorld(Grid(400, 1));
  const PoseGraph<Pose2> two = CutAt(world.graph, {150});
  const std::vector<ChainSpan> spans = ChainSpansOf(two);
  ASSERT_EQ(spans.size(), 2u);
  EXPECT_EQ(spans[0].first, 0);
  EXPECT_EQ(spans[0].last, 149);
  EXPECT_EQ(spans[1].first, 150);
  EXPECT_EQ(spans[1].last, 399);
  EXPECT_EQ(ChainHolding(spans, 149), 0);
  EXPECT_EQ(ChainHolding(spans, 150), 1);
}

TEST(VerifyChains, TwoSessionsOfOneWorldAreJoinedByTheirLoops) {
  const SimulatedWorld world = SimulateWorld(Grid(1200, 3));
  const int cut = 600;
  const PoseGraph<Pose2> two = CutAt(world.graph, {cut});
  int across = 0;
  for (const auto& e : two.loops()) {
    across += (e.from < cut) != (e.to < cut);
  }
  ASSERT_GT(across, 10);
  const ChainsVerdict<Pose2> v = VerifyChains(two, ChainWorldOptions());
  ASSERT_EQ(v.chains.size(), 2u);
  ASSERT_EQ(v.pairs.size(), 1u);
  const ChainPair<Pose2>& pair = v.pairs[0];
  EXPECT_TRUE(pair.joined);
  EXPECT_EQ(static_cast<int>(pair.candidates.size()), across);
  // Every loop is true: (nearly) all between the chains are kept.
  EXPECT_GE(pair.accepted.size(), 0.9 * across);
  EXPECT_EQ(v.map_of_chain, (std::vector<int>{0, 0}));
  // The joined map puts the second session where the removed odometry step
  // says, relative to the first session's last pose.
  const Pose2 step = v.estimates[cut - 1].between(v.estimates[cut]);
  const Pose2 truth = world.truth[cut - 1].between(world.truth[cut]);
  EXPECT_LT((step.translation() - truth.translation()).norm(), 0.3);
  // Loops inside each chain are judged as the chain alone would judge them.
  for (const int k : v.verdict.accepted) {
    const auto& e = two.loops()[k];
    if ((e.from < cut) != (e.to < cut)) {
      const DecisionTest test = v.verdict.reasons[k].test;
      EXPECT_TRUE(test == DecisionTest::kJoin || test == DecisionTest::kMap);
    }
  }
}

TEST(VerifyChains, RevisitsFarApartJoinSessionsWhateverTheDriftBetweenThem) {
  // Two sessions whose 24 loops between them make five revisits far apart
  // (up to 500 poses on one chain), with 200 false loops between them. Each
  // session's map holds by its own loops; the odometry's drift between the
  // revisits does not: placed by one revisit, the other revisits' links
  // miss the second map by far more than their noise (the 24 would be left
  // apart by a rule that required that), but one placement of the second
  // map fits them all.
  const SimulatedWorld world = SimulateWorld(Grid(1000, 4));
  size_t true_loops = 0;
  const PoseGraph<Pose2> two =
      TwoSessionsWithFalseLoops(world, 500, &true_loops);
  const ChainsVerdict<Pose2> v = VerifyChains(two, ChainWorldOptions());
  ASSERT_EQ(v.pairs.size(), 1u);
  EXPECT_TRUE(v.pairs[0].joined);
  int true_between = 0, false_kept = 0;
  for (const int k : v.pairs[0].candidates) {
    true_between += static_cast<size_t>(k) < true_loops;
  }
  for (const int k : v.pairs[0].accepted) {
    false_kept += static_cast<size_t>(k) >= true_loops;
  }
  EXPECT_EQ(true_between, 24);
  EXPECT_EQ(false_kept, 0);
  EXPECT_EQ(v.pairs[0].accepted.size(), 24u);
}

TEST(VerifyChains, DecisionsDoNotDependOnTheThreads) {
  // Two sessions joined by their true loops, with groups of five false loops
  // between them that agree with themselves: rule 1 weighs what each link
  // of a cluster brings, solves that run side by side with more threads.
  const SimulatedWorld world = SimulateWorld(Grid(1000, 4));
  PoseGraph<Pose2> two = CutAt(world.graph, {500});
  FalseLoopOptions spoil;
  spoil.count = 100;
  spoil.group = 5;
  spoil.between_chains = true;
  spoil.seed = 11;
  AddFalseLoops(&two, spoil);
  RrrOptions options = ChainWorldOptions();
  const ChainsVerdict<Pose2> one = VerifyChains(two, options);
  ASSERT_EQ(one.pairs.size(), 1u);
  EXPECT_TRUE(one.pairs[0].joined);
  // Rule 1 refused some clusters: their links do not agree.
  int own = 0;
  for (const int k : one.pairs[0].candidates) {
    own += one.verdict.reasons[k].test == DecisionTest::kOwn;
  }
  EXPECT_GT(own, 0);
  for (const int threads : {2, 3}) {
    options.threads = threads;
    const ChainsVerdict<Pose2> many = VerifyChains(two, options);
    EXPECT_EQ(many.verdict.accepted, one.verdict.accepted) << threads;
    EXPECT_EQ(many.verdict.rejected, one.verdict.rejected) << threads;
    for (const int k : one.pairs[0].candidates) {
      EXPECT_EQ(many.verdict.reasons[k].test, one.verdict.reasons[k].test);
      EXPECT_EQ(many.verdict.reasons[k].statistic,
                one.verdict.reasons[k].statistic);
    }
  }
}

TEST(VerifyChains, ThreeSessionsMakeOneMapWithTheLoopsOfEveryPair) {
  // The pairs judged after two joins hold their chains in one map already;
  // their loops are judged against it, whichever chains lie between them.
  const SimulatedWorld world = SimulateWorld(Grid(1500, 3));
  const std::vector<int> cuts = {500, 1000};
  const PoseGraph<Pose2> three = CutAt(world.graph, cuts);
  const ChainsVerdict<Pose2> v = VerifyChains(three, ChainWorldOptions());
  ASSERT_EQ(v.chains.size(), 3u);
  EXPECT_EQ(v.map_of_chain, (std::vector<int>{0, 0, 0}));
  for (const ChainPair<Pose2>& pair : v.pairs) {
    // Every loop is true: (nearly) all between the chains are kept.
    EXPECT_GE(pair.accepted.size(), 0.9 * pair.candidates.size())
        << pair.first << "-" << pair.second;
  }
  for (const int cut : cuts) {
    const Pose2 step = v.estimates[cut - 1].between(v.estimates[cut]);
    const Pose2 truth = world.truth[cut - 1].between(world.truth[cut]);
    EXPECT_LT((step.translation() - truth.translation()).norm(), 0.3) << cut;
  }
}

TEST(VerifyChains, AJoinThatStrongerJoinsContradictIsRefused) {
  // Three sessions of one world; the first two never revisit each other's
  // places, but between them come about 80 random false loops and two false
  // revisits of two links each that agree on one wrong placement of the
  // second session (the same look-alike offset twice, as in a building
  // whose floors repeat): alone they would join the two wrongly, and that
  // pair has the most candidates. The joins of the third session with each
  // of the others rest on more evidence: made first, they put all three in
  // one map, and the false revisits are judged against it and refused.
  const SimulatedWorld world = SimulateWorld(Grid(1500, 3));
  const std::vector<int> cuts = {500, 1000};
  size_t true_loops = 0;
  const PoseGraph<Pose2> three =
      ThreeSessionsWithAFalseJoin(world, cuts, &true_loops);
  const ChainsVerdict<Pose2> v = VerifyChains(three, ChainWorldOptions());
  ASSERT_EQ(v.chains.size(), 3u);
  ASSERT_EQ(v.pairs.size(), 3u);
  EXPECT_GT(v.pairs[0].candidates.size(), v.pairs[2].candidates.size());
  EXPECT_EQ(v.map_of_chain, (std::vector<int>{0, 0, 0}));
  EXPECT_TRUE(v.pairs[0].accepted.empty());
  for (const int k : v.verdict.accepted) {
    EXPECT_LT(static_cast<size_t>(k), true_loops) << "false loop accepted";
  }
  for (const ChainPair<Pose2>& pair : v.pairs) {
    if (pair.first == 0 && pair.second == 1) continue;
    EXPECT_GE(pair.accepted.size(), 0.9 * pair.candidates.size())
        << pair.first << "-" << pair.second;
  }
  // Every session where it was, relative to the first.
  for (const int p : {cuts[0], cuts[1]}) {
    const Pose2 start = v.estimates[0].between(v.estimates[p]);
    const Pose2 truth = world.truth[0].between(world.truth[p]);
    EXPECT_LT((start.translation() - truth.translation()).norm(), 1.0) << p;
  }
}

TEST(VerifyChains, ALoopRefusedByTheBoundIsOneAFullMinimizationRefuses) {
  // Two sessions of one world with 200 false loops between them. Once the
  // sessions are joined, most false loops are refused by the lower bound of
  // what they would bring (test "map_bound"), without a trial: each must be
  // one that minimizing the whole joined map with it refuses too.
  const SimulatedWorld world = SimulateWorld(Grid(1200, 3));
  size_t true_loops = 0;
  const PoseGraph<Pose2> two =
      TwoSessionsWithFalseLoops(world, 600, &true_loops);
  const ChainsVerdict<Pose2> v = VerifyChains(two, ChainWorldOptions());
  ASSERT_EQ(v.pairs.size(), 1u);
  ASSERT_TRUE(v.pairs[0].joined);
  int true_between = 0, true_kept = 0;
  for (const int k : v.pairs[0].candidates) {
    if (static_cast<size_t>(k) >= true_loops) {
      EXPECT_FALSE(std::binary_search(v.verdict.accepted.begin(),
                                      v.verdict.accepted.end(), k))
          << "false loop " << k << " accepted";
      continue;
    }
    ++true_between;
    true_kept += std::binary_search(v.verdict.accepted.begin(),
                                    v.verdict.accepted.end(), k);
  }
  EXPECT_GE(true_kept, 0.9 * true_between);
  const PoseGraphSolver<Pose2> solver(two, 1);
  MinimizeResult without;
  solver.Optimize(v.verdict.accepted, ConvergenceOptions{}, &without,
                  &v.estimates);
  int bounded = 0;
  for (const int k : v.pairs[0].candidates) {
    const DecisionReason& r = v.verdict.reasons[k];
    if (r.test != DecisionTest::kMapBound || bounded == 20) continue;
    ++bounded;
    EXPECT_GE(r.statistic, r.gate);
    std::vector<int> with = v.verdict.accepted;
    with.push_back(k);
    MinimizeResult result;
    solver.Optimize(with, ConvergenceOptions{}, &result, &v.estimates);
    EXPECT_GT(result.final_chi2 - without.final_chi2, r.gate) << k;
  }
  EXPECT_EQ(bounded, 20);
}

TEST(VerifyChains, RobotsThatNeverMeetAreNeverJoinedByFalseLoops) {
  // Two robots in two cities; their recognisers report 1,000 false loops
  // between them, half in groups of five that agree with themselves.
  PoseGraph<Pose2> fleet;
  AppendChain(SimulateWorld(Grid(600, 5)), Pose2(), &fleet);
  AppendChain(SimulateWorld(Grid(600, 6)), Pose2(500.0, 0.0, 0.3), &fleet);
  std::vector<int> inside_a;
  for (size_t k = 0; k < fleet.loops().size(); ++k) {
    if (fleet.loops()[k].from < 600) inside_a.push_back(static_cast<int>(k));
  }
  for (const int group : {1, 5}) {
    FalseLoopOptions spoil;
    spoil.count = 500;
    spoil.group = group;
    spoil.between_chains = true;
    spoil.seed = 7 + group;
    for (const int k : AddFalseLoops(&fleet, spoil)) {
      const auto& e = fleet.loops()[k];
      ASSERT_NE(e.from < 600, e.to < 600) << "not between the chains";
    }
  }
  const ChainsVerdict<Pose2> v = VerifyChains(fleet, ChainWorldOptions());
  ASSERT_EQ(v.pairs.size(), 1u);
  EXPECT_EQ(v.pairs[0].candidates.size(), 1000u);
  EXPECT_FALSE(v.pairs[0].joined);
  EXPECT_TRUE(v.pairs[0].accepted.empty());
  EXPECT_EQ(v.map_of_chain, (std::vector<int>{0, 1}));
  int apart = 0;
  for (const int k : v.pairs[0].candidates) {
    apart += v.verdict.reasons[k].test == DecisionTest::kApart;
  }
  EXPECT_GT(apart, 0);
  // The first robot's own loops are judged as its chain alone judges them.
  const std::vector<int> alone =
      VerifyWithMap(SubGraph(fleet, {v.chains[0]}, fleet.estimates(), inside_a),
                    ChainWorldOptions())
          .accepted;
  int accepted_a = 0;
  for (const int k : v.verdict.accepted) {
    accepted_a += fleet.loops()[k].from < 600;
  }
  EXPECT_EQ(accepted_a, static_cast<int>(alone.size()));
}

TEST(VerifyChains, TrueLinksOutnumberedInTheirClusterAreJudgedAgain) {
  // Two sessions joined by their revisits. Into one revisit between them
  // go twice as many false links as it has true ones, at the same poses:
  // they agree with each other exactly (the second session moved by
  // `wrong`), so rule 1, taking out one link at a time, keeps them and
  // takes out the true ones. The joined map refuses them; the true links
  // are then judged again, and kept. With a second false group at the same
  // poses, larger still, rule 1 keeps that, then of the links it took out
  // the first group; the map refuses both, and the true links, judged
  // again twice, are kept.
  const SimulatedWorld world = SimulateWorld(Grid(1200, 3));
  const int cut = 600;
  const PoseGraph<Pose2> two = CutAt(world.graph, {cut});
  const std::vector<std::vector<int>> runs = RunsBetween(two, cut);
  const auto first_long = std::find_if(
      runs.begin(), runs.end(), [](const auto& r) { return r.size() >= 4; });
  ASSERT_NE(first_long, runs.end());
  const std::vector<int>& revisit = *first_long;
  std::vector<Constraint<Pose2>> falses =
      CopiesMovedBy(two, world.truth, revisit, Pose2(2.0, 1.0, 0.05), {0, 1});
  for (const DecisionReason& r :
       RevisitKeptFalseRefused(two, revisit, falses)) {
    EXPECT_NE(r.test, DecisionTest::kNotJudged);
  }
  for (const auto& e : CopiesMovedBy(two, world.truth, revisit,
                                     Pose2(-1.5, 2.0, -0.1), {0, 1, 2})) {
    falses.push_back(e);
  }
  RevisitKeptFalseRefused(two, revisit, falses);
}

TEST(VerifyChains, FalseLinksInALongRevisitBetweenChainsAreTakenOutByRule1) {
  // Two sessions joined by their revisits. Into the longest revisit between
  // them go two false links, each its own wrong pose, at poses of the
  // revisit: rule 1 takes out exactly those (kOwnLink), and the true links
  // of the revisit are kept.
  const SimulatedWorld world = SimulateWorld(Grid(1200, 3));
  const int cut = 600;
  PoseGraph<Pose2> two = CutAt(world.graph, {cut});
  const std::vector<std::vector<int>> runs = RunsBetween(two, cut);
  const std::vector<int> longest = *std::max_element(
      runs.begin(), runs.end(),
      [](const auto& a, const auto& b) { return a.size() < b.size(); });
  ASSERT_GE(longest.size(), 8u);
  std::vector<Constraint<Pose2>> falses;
  for (const auto& [at, wrong] :
       {std::pair<size_t, Pose2>{2, Pose2(1.5, -1.0, 0.2)},
        std::pair<size_t, Pose2>{5, Pose2(-2.0, 0.5, -0.15)}}) {
    Constraint<Pose2> e = two.loops()[longest[at]];
    e.to += 1;
    e.measurement = world.truth[e.from].between(wrong * world.truth[e.to]);
    falses.push_back(e);
  }
  for (const DecisionReason& r :
       RevisitKeptFalseRefused(two, longest, falses)) {
    EXPECT_EQ(r.test, DecisionTest::kOwnLink);
  }
}

TEST(VerifyChains, OneFalseClusterCannotJoinTwoChainsAlone) {
  // Two robots that never meet, and one group of six false loops between
  // them that agree with each other exactly: consistent, but alone.
  PoseGraph<Pose2> fleet;
  AppendChain(SimulateWorld(Grid(400, 8)), Pose2(), &fleet);
  AppendChain(SimulateWorld(Grid(400, 9)), Pose2(0.0, 300.0, 0.0), &fleet);
  const Pose2 wrong(1.0, 0.5, 0.1);
  for (int k = 0; k < 6; ++k) {
    Constraint<Pose2> e;
    e.from = 100 + k;
    e.to = 600 + k;
    e.measurement =
        fleet.estimates()[e.from].between(wrong * fleet.estimates()[e.to]);
    fleet.AddEdge(e);
  }
  const ChainsVerdict<Pose2> v = VerifyChains(fleet, ChainWorldOptions());
  ASSERT_EQ(v.pairs.size(), 1u);
  EXPECT_FALSE(v.pairs[0].joined);
  EXPECT_TRUE(v.pairs[0].accepted.empty());
}

TEST(VerifyChains, RobotsThatMeetOnceAmongFalseLoopsAreLeftApartAndSaySo) {
  // One true revisit between two robots (eight links that agree with where
  // the robots really were) among 100 random false loops: one cluster is
  // not evidence enough, so the robots stay apart, and every loop between
  // them says why.
  PoseGraph<Pose2> fleet;
  const SimulatedWorld a = SimulateWorld(Grid(400, 12));
  const SimulatedWorld b = SimulateWorld(Grid(400, 13));
  AppendChain(a, Pose2(), &fleet);
  const Pose2 where(3.0, 1.0, 0.2);  // b's frame in a's
  AppendChain(b, where, &fleet);
  for (int k = 0; k < 8; ++k) {
    Constraint<Pose2> e;
    e.from = 200 + k;
    e.to = 400 + 100 + k;
    e.measurement = a.truth[200 + k].between(where * b.truth[100 + k]);
    fleet.AddEdge(e);
  }
  FalseLoopOptions spoil;
  spoil.count = 100;
  AddFalseLoops(&fleet, spoil);
  const ChainsVerdict<Pose2> v = VerifyChains(fleet, ChainWorldOptions());
  ASSERT_EQ(v.pairs.size(), 1u);
  EXPECT_FALSE(v.pairs[0].joined);
  for (const int k : v.pairs[0].candidates) {
    EXPECT_NE(
        std::find(v.verdict.rejected.begin(), v.verdict.rejected.end(), k),
        v.verdict.rejected.end());
  }
}

TEST(VerifyChains, AFalseRevisitInsideAChainIsRefutedByTheMapThatJoinsIt) {
  // The second session alone accepts a false revisit that its drift
  // explains; the loops between the sessions, true revisits of the other
  // sessions' places, contradict it once the sessions are joined. With a
  // third session, the second's first join is reviewed while pairs remain.
  const SimulatedWorld world = SimulateWorld(Grid(1600, 4));
  const Verdict one = VerifyWithMap(world.graph, ChainWorldOptions());
  for (const std::vector<int>& cuts :
       {std::vector<int>{800}, std::vector<int>{800, 1400}}) {
    SCOPED_TRACE(::testing::PrintToString(cuts));
    size_t true_loops = 0;
    const PoseGraph<Pose2> sessions =
        SessionsWithAFalseRevisit(world, cuts, &true_loops);
    std::vector<int> inside;
    const Verdict alone =
        JudgedAlone(sessions, ChainSpansOf(sessions)[1], &inside);
    const int false_alone = static_cast<int>(std::count_if(
        alone.accepted.begin(), alone.accepted.end(),
        [&](int k) { return static_cast<size_t>(inside[k]) >= true_loops; }));
    ASSERT_GT(false_alone, 0);

    const ChainsVerdict<Pose2> v = VerifyChains(sessions, ChainWorldOptions());
    ASSERT_EQ(v.map_of_chain, std::vector<int>(cuts.size() + 1, 0));
    int refuted_by_map = 0;
    for (size_t k = true_loops; k < sessions.loops().size(); ++k) {
      EXPECT_THAT(v.verdict.rejected, ::testing::Contains(k));
      const DecisionReason& r = v.verdict.reasons[k];
      if (r.test != DecisionTest::kJoinedMap) continue;
      ++refuted_by_map;
      EXPECT_GT(r.statistic, r.gate);
    }
    EXPECT_EQ(refuted_by_map, false_alone);
    // What the revisit had bent is judged afresh: the sessions keep as many
    // true loops as the uncut world judged as one chain does.
    EXPECT_GE(v.verdict.accepted.size(), one.accepted.size());
  }
}

// `sessions` with one in `every` kept of its first `*true_loops` loops
// (which it updates) that are between chains and reach no pose from
// `before` on, and every other loop.
PoseGraph<Pose2> ThinnedBetweenChains(const PoseGraph<Pose2>& sessions,
                                      int before, int every,
                                      size_t* true_loops) {
  const std::vector<ChainSpan> chains = ChainSpansOf(sessions);
  PoseGraph<Pose2> out;
  for (int p = 0; p < sessions.num_poses(); ++p) {
    out.AddPose(sessions.ids()[p], sessions.estimates()[p]);
  }
  for (const auto& e : sessions.odometry()) out.AddEdge(e);
  size_t kept = 0;
  int thinned = 0;
  for (size_t k = 0; k < sessions.loops().size(); ++k) {
    const auto& e = sessions.loops()[k];
    const bool thin =
        k < *true_loops && std::max(e.from, e.to) < before &&
        ChainHolding(chains, e.from) != ChainHolding(chains, e.to);
    if (thin && thinned++ % every != 0) continue;
    out.AddEdge(e);
    if (k < *true_loops) ++kept;
  }
  *true_loops = kept;
  return out;
}

TEST(VerifyChains,
     SmallRevisitsBetweenChainsTogetherRefuteAFalseRevisitInside) {
  // As above, with a false revisit of 6 links (poses 900–905 to 1300–1305),
  // and of the true loops between the sessions that reach only poses before
  // 1310 (those the revisit moves against the places the sessions are
  // joined by) one in 2 kept: small clusters, none of which outweighs the
  // revisit, so rule 3 refuses them against the map it bent, and the
  // joined map's accepted loops fit it. Together, the refused clusters that
  // would fit without it outweigh it (rule 5's coalition).
  const SimulatedWorld world = SimulateWorld(Grid(1600, 4));
  size_t true_loops = 0;
  const PoseGraph<Pose2> spoiled = ThinnedBetweenChains(
      SessionsWithAFalseRevisit(world, {800}, &true_loops, 6), 1310, 2,
      &true_loops);
  const PoseGraph<Pose2> cut = CutAt(world.graph, {800});
  size_t clean_loops = cut.loops().size();
  const PoseGraph<Pose2> clean =
      ThinnedBetweenChains(cut, 1310, 2, &clean_loops);
  ASSERT_EQ(clean_loops, true_loops);
  std::vector<int> inside;
  const Verdict alone = JudgedAlone(spoiled, ChainSpansOf(spoiled)[1], &inside);
  ASSERT_GT(std::count_if(alone.accepted.begin(), alone.accepted.end(),
                          [&](int k) {
                            return static_cast<size_t>(inside[k]) >= true_loops;
                          }),
            0);

  const ChainsVerdict<Pose2> v = VerifyChains(spoiled, ChainWorldOptions());
  ASSERT_EQ(v.map_of_chain, std::vector<int>(2, 0));
  for (size_t k = true_loops; k < spoiled.loops().size(); ++k) {
    EXPECT_THAT(v.verdict.rejected, ::testing::Contains(k));
    const DecisionReason& r = v.verdict.reasons[k];
    EXPECT_THAT(r.test, ::testing::AnyOf(DecisionTest::kJoinedMap,
                                         DecisionTest::kOutweighed));
    EXPECT_GT(r.statistic, r.gate);
  }
  // The sessions keep the true loops they keep without the false revisit.
  const ChainsVerdict<Pose2> without = VerifyChains(clean, ChainWorldOptions());
  EXPECT_EQ(v.verdict.accepted, without.verdict.accepted);
}

TEST(VerifyChains, OneChainIsJudgedAsTheMapProcedureJudgesIt) {
  WorldOptions world_options = Grid(500, 11);
  world_options.false_loops = 20;
  const SimulatedWorld world = SimulateWorld(world_options);
  const ChainsVerdict<Pose2> v = VerifyChains(world.graph, ChainWorldOptions());
  EXPECT_TRUE(v.pairs.empty());
  EXPECT_EQ(v.verdict.accepted,
            VerifyWithMap(world.graph, ChainWorldOptions()).accepted);
}

}  // namespace
}  // namespace rrr
