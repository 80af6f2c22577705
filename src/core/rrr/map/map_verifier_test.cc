// The map procedure: decisions on generated worlds, independence from when
// updates run, reversals both ways, 3D.
#include "rrr/rrr/map/map_verifier.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <set>

#include "../../testing/noisy_chain.h"
#include "../../testing/replay.h"
#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/rrr/map/verify_with_map.h"
#include "rrr/sim/simulated_world.h"

namespace rrr {
namespace {

using Replay = testing::Replay<MapVerifier<Pose2>, Pose2>;

// The grid world with `poses` poses and `false_loops` false loops in groups
// of `group`, drawn with `seed`.
SimulatedWorld World(int poses, int false_loops, int group,
                     std::uint64_t seed = 1) {
  WorldOptions world;
  world.poses = poses;
  world.false_loops = false_loops;
  world.group = group;
  world.seed = seed;
  return SimulateWorld(world);
}

// The end ids of the world's false loops.
testing::Pairs FalsePairs(const SimulatedWorld& w) {
  testing::Pairs out;
  for (const int k : w.false_loops) {
    const auto& l = w.graph.loops()[k];
    out.insert({w.graph.ids()[l.from], w.graph.ids()[l.to]});
  }
  return out;
}

TEST(MapVerifier, AcceptsNoFalseLoopOfASpoiledWorld) {
  for (const int group : {1, 4}) {
    const SimulatedWorld w = World(2000, 60, group);
    const Replay replay(w.graph, RrrOptions());
    const testing::Pairs accepted = replay.Accepted();
    const testing::Pairs wrong = FalsePairs(w);
    int true_accepted = 0;
    for (const auto& pair : accepted) {
      EXPECT_EQ(wrong.count(pair), 0u) << pair.first << "-" << pair.second;
      true_accepted += wrong.count(pair) == 0;
    }
    const int true_loops =
        static_cast<int>(w.graph.loops().size() - w.false_loops.size());
    EXPECT_GE(true_accepted, 0.95 * true_loops) << "group " << group;
    EXPECT_EQ(replay.verifier.num_waiting(), 0);
    int by_scan[3] = {0, 0, 0};
    for (int c = 0; c < replay.verifier.num_candidates(); ++c) {
      EXPECT_NE(replay.verifier.state(c), LoopState::kPending);
      ++by_scan[static_cast<int>(replay.verifier.state(c))];
    }
    for (const LoopState s :
         {LoopState::kPending, LoopState::kAccepted, LoopState::kRejected}) {
      EXPECT_EQ(replay.verifier.num_in_state(s), by_scan[static_cast<int>(s)])
          << ToString(s);
    }
    EXPECT_GT(replay.verifier.num_in_state(LoopState::kRejected), 0);
  }
}

void ExpectNoFalseLoopAccepted(const SimulatedWorld& w,
                               const Verdict& verdict) {
  const testing::Pairs wrong = FalsePairs(w);
  for (const int k : verdict.accepted) {
    const auto& l = w.graph.loops()[k];
    EXPECT_EQ(wrong.count({w.graph.ids()[l.from], w.graph.ids()[l.to]}), 0u)
        << k;
  }
}

// The indices of the world's true loops, in order.
std::vector<int> TrueLoops(const SimulatedWorld& w) {
  std::vector<int> out;
  for (int k = 0; k < static_cast<int>(w.graph.loops().size()); ++k) {
    if (std::find(w.false_loops.begin(), w.false_loops.end(), k) ==
        w.false_loops.end()) {
      out.push_back(k);
    }
  }
  return out;
}

// A world of 1000 poses and 300 false loops in groups of ten.
SimulatedWorld CrowdedWorld(std::uint64_t seed) {
  return World(1000, 300, 10, seed);
}

TEST(MapVerifier, LeavesOutTheLinksTheOdometryRefutesAlone) {
  // In this world, links of false groups that the odometry refutes on their
  // own share clusters with revisits; each is refused alone (left in, they
  // would pull the cluster's own test off the revisits).
  const SimulatedWorld w = CrowdedWorld(9);
  const Verdict verdict = VerifyWithMap(w.graph, RrrOptions());
  EXPECT_EQ(verdict.accepted, TrueLoops(w));
  int refused_alone = 0;
  for (const int k : w.false_loops) {
    const DecisionReason& r = verdict.reasons[k];
    if (r.test != DecisionTest::kAlone) continue;
    ++refused_alone;
    EXPECT_GE(r.statistic, r.gate) << k;
    EXPECT_EQ(r.dof, 3);
  }
  EXPECT_GT(refused_alone, 0);
}

TEST(MapVerifier, AcceptsNoLinkOfAFalseGroupThatTheOdometryPartlyRefutes) {
  // Here six links of a false group fit the odometry while its other four
  // refute it. None of the six may be accepted.
  const SimulatedWorld w = CrowdedWorld(3);
  const Verdict verdict = VerifyWithMap<Pose2>(w.graph, RrrOptions());
  ExpectNoFalseLoopAccepted(w, verdict);
  EXPECT_GE(verdict.accepted.size(), 150u);
}

TEST(MapVerifier, KeepsARevisitThatAFalseGroupJoins) {
  // In this world (groups of ten false loops, seed 8) a false group falls
  // into one cluster with a revisit.
  const SimulatedWorld w = World(2000, 100, 10, 8);
  EXPECT_EQ(VerifyWithMap(w.graph, RrrOptions()).accepted, TrueLoops(w));
}

TEST(MapVerifier, LetsTheMapChooseBetweenTwoGroupsOfACluster) {
  // The world of `rrr simulate --poses 900 --false-loops 30 --group 3
  // --seed 4`: a false group of three shares a cluster with a revisit of
  // five. Against the odometry alone each group agrees with itself and the
  // three outvote the five; against the map the larger group is tried
  // first and fits.
  const SimulatedWorld w = World(900, 30, 3, 4);
  const Verdict verdict = VerifyWithMap<Pose2>(w.graph, RrrOptions());
  ExpectNoFalseLoopAccepted(w, verdict);
  // The revisit: the true loops that share a cluster with a false loop.
  std::set<int> false_clusters;
  for (const int k : w.false_loops)
    false_clusters.insert(verdict.cluster_of_loop[k]);
  std::vector<int> revisit;
  for (const int k : TrueLoops(w)) {
    if (false_clusters.count(verdict.cluster_of_loop[k])) revisit.push_back(k);
  }
  ASSERT_EQ(revisit.size(), 5u);
  for (const int k : revisit) {
    EXPECT_TRUE(
        std::binary_search(verdict.accepted.begin(), verdict.accepted.end(), k))
        << "revisit link " << k;
    EXPECT_EQ(verdict.reasons[k].test, DecisionTest::kMap);
    EXPECT_LT(verdict.reasons[k].statistic, verdict.reasons[k].gate);
  }
  EXPECT_GE(verdict.accepted.size(), 0.9 * TrueLoops(w).size());
}

TEST(MapVerifier, DecisionsDoNotDependOnWhenUpdatesRun) {
  const SimulatedWorld w = World(1500, 40, 3);
  const RrrOptions options;
  const Replay every_pose(w.graph, options, 1);
  const Replay every_13(w.graph, options, 13);
  const Replay at_the_end(w.graph, options, w.graph.num_poses() + 1);
  EXPECT_FALSE(every_pose.Accepted().empty());
  EXPECT_EQ(every_13.Accepted(), every_pose.Accepted());
  EXPECT_EQ(at_the_end.Accepted(), every_pose.Accepted());
  // Not only the decisions: each one's reason and the scale in force are
  // the same, as if updated after every pose whenever updates run.
  for (const Replay* other : {&every_13, &at_the_end}) {
    for (int c = 0; c < every_pose.verifier.num_candidates(); ++c) {
      const DecisionReason a = every_pose.verifier.reason(c);
      const DecisionReason b = other->verifier.reason(c);
      EXPECT_EQ(ToString(a.test), ToString(b.test)) << c;
      EXPECT_EQ(a.statistic, b.statistic) << c;
      EXPECT_EQ(a.gate, b.gate) << c;
      EXPECT_EQ(a.pose, b.pose) << c;
    }
    EXPECT_EQ(other->verifier.noise_scale(), every_pose.verifier.noise_scale());
  }
  // VerifyWithMap is the replay after every pose.
  const Verdict verdict = VerifyWithMap(w.graph, options);
  testing::Pairs batch;
  for (const int k : verdict.accepted) {
    const auto& l = w.graph.loops()[k];
    batch.insert({w.graph.ids()[l.from], w.graph.ids()[l.to]});
  }
  EXPECT_EQ(batch, every_pose.Accepted());
}

TEST(MapVerifier, ReadingTheMapChangesNoDecision) {
  // Loops come up to two poses after their later pose, as on another topic;
  // a node reads the newest pose's estimate (for tf) after every update, and
  // the whole map at times.
  const SimulatedWorld w = World(1500, 40, 3);
  const RrrOptions options;
  const Replay unread(w.graph, options, 1, 2);
  MapVerifier<Pose2> read(options);
  int updates = 0;
  FeedInArrivalOrder(
      w.graph, &read, 1,
      [&](const std::vector<DecisionChange>&) {
        read.MapAt({read.graph().num_poses() - 1});
        if (++updates % 50 == 0) read.Map();
      },
      2);
  ASSERT_FALSE(unread.Accepted().empty());
  ASSERT_EQ(read.num_candidates(), unread.verifier.num_candidates());
  for (int c = 0; c < read.num_candidates(); ++c) {
    EXPECT_EQ(read.state(c), unread.verifier.state(c)) << c;
    EXPECT_EQ(read.reason(c).statistic, unread.verifier.reason(c).statistic)
        << c;
  }
}

// Laps of a circle of kLap poses, exact odometry that is stiff in
// translation, with the given rotation information. Loops are added as
// `(a, b, measured as the truth of (a, b + shift))`, stiff in both.
constexpr int kLap = 400;
struct Circle {
  PoseGraph<Pose2> graph;
  std::vector<Pose2> truth;

  explicit Circle(int laps = 2, double rotation_information = 1e4) {
    const double step = 2.0 * M_PI / kLap;
    for (int k = 0; k < laps * kLap; ++k) {
      truth.push_back(k == 0 ? Pose2() : truth.back() * Pose2(1.0, 0.0, step));
      graph.AddPose(k, truth.back());
    }
    Pose2::Jacobian info = Pose2::Jacobian::Identity();
    info.diagonal() << 100.0, 100.0, rotation_information;
    for (int k = 0; k + 1 < laps * kLap; ++k) {
      graph.AddEdge({k, k + 1, truth[k].between(truth[k + 1]), info});
    }
  }
  void AddLoops(int a, int b, int count, int shift) {
    for (int k = 0; k < count; ++k) {
      AddLoop(a + k, b + k, truth[a + k].between(truth[b + k + shift]));
    }
  }
  void AddLoop(int a, int b, const Pose2& measurement) {
    Pose2::Jacobian info = Pose2::Jacobian::Identity();
    info.diagonal() << 100.0, 100.0, 1e4;
    graph.AddEdge({a, b, measurement, info});
  }
  // Adds a loop (a, b) measured `sideways` m to the side of the truth;
  // returns its loop index.
  int AddShiftedLoop(int a, int b, double sideways) {
    const int index = static_cast<int>(graph.loops().size());
    AddLoop(a, b, truth[a].between(truth[b]) * Pose2(0.0, sideways, 0.0));
    return index;
  }
  // Runs the map procedure with the information matrices as given (s = 1)
  // and expects exactly the loops `rejected` to be refused, each by a test
  // against the map (none outweighed by a later cluster).
  void ExpectRefusedByTheMap(const std::vector<int>& rejected) const {
    RrrOptions options;
    options.noise_scale = 1.0;
    const Verdict verdict = VerifyWithMap<Pose2>(graph, options);
    EXPECT_EQ(verdict.rejected, rejected);
    for (const int k : verdict.rejected) {
      const DecisionTest test = verdict.reasons[k].test;
      EXPECT_TRUE(test == DecisionTest::kMapLink || test == DecisionTest::kMap)
          << k << ": " << ToString(test);
      EXPECT_GE(verdict.reasons[k].statistic, verdict.reasons[k].gate) << k;
    }
  }
};

TEST(MapVerifier, ReversesDecisionsBothWaysOnNewEvidence) {
  Circle circle;
  // F, first: five false links that claim lap 2 is ten poses further on.
  circle.AddLoops(30, kLap + 20, 5, -10);
  // T0: one true link, weaker than F; T1: ten true links.
  circle.AddLoops(50, kLap + 50, 1, 0);
  circle.AddLoops(80, kLap + 80, 10, 0);
  RrrOptions options;
  options.noise_scale = 1.0;
  const Replay replay(circle.graph, options);
  // Along the way F was accepted and dropped, T0 rejected and accepted...
  EXPECT_GT(replay.accepted_then_rejected, 0);
  EXPECT_GT(replay.rejected_then_accepted, 0);
  // ... F because T1 outweighed it: in the joint solve F was the less
  // consistent (what it brings over its gate above T1's) ...
  const Verdict verdict = VerifyWithMap<Pose2>(circle.graph, options);
  for (int k = 0; k < 5; ++k) {
    const DecisionReason& f = verdict.reasons[k];
    EXPECT_EQ(f.test, DecisionTest::kOutweighed) << k;
    EXPECT_GT(f.statistic, f.gate) << k;
    EXPECT_EQ(f.by_cluster, verdict.cluster_of_loop[6]);
  }
  // ... and the end holds exactly the true links.
  testing::Pairs truth;
  truth.insert({50, kLap + 50});
  for (int k = 0; k < 10; ++k) truth.insert({80 + k, kLap + 80 + k});
  EXPECT_EQ(replay.Accepted(), truth);
}

TEST(MapVerifier, DropsTheLinkOfAClusterThatOnlyTheMapRefutes) {
  // Three laps, odometry soft in rotation: lap 2 and lap 3 are tied to lap 1
  // at poses 100-119 and 100-111 (lap-2 links, then lap-3 links, judged
  // first). Cluster C links lap 3 to lap 2: five true links at 100-104 and
  // F at 112, 1.5 m to the side. Alone with the odometry C is consistent
  // (eight soft steps on each lap absorb F); in the map, F's ends are one
  // step from tied poses, so C fails as a whole and F is dropped.
  Circle circle(3, 100.0);
  circle.AddLoops(100, kLap + 100, 20, 0);
  circle.AddLoops(100, 2 * kLap + 100, 12, 0);
  circle.AddLoops(kLap + 100, 2 * kLap + 100, 5, 0);
  const int f = circle.AddShiftedLoop(kLap + 112, 2 * kLap + 112, 1.5);
  circle.ExpectRefusedByTheMap({f});
}

TEST(MapVerifier, DropsAFalseGroupThatRidesInARevisit) {
  // Lap 2 and lap 3 are tied to lap 1 at poses 100-129 and 100-120. Cluster
  // C links lap 3 to lap 2: twenty true links at 90-104 and 120-124 and a
  // false group G of five consecutive links at 112-116, 1.5 m to the side
  // and consistent with each other. Alone with the odometry C bends and
  // passes; in the map G fails link by link, more links than pruning
  // drops: the links that fit are tried alone and accepted without G.
  Circle circle(3, 100.0);
  circle.AddLoops(100, kLap + 100, 30, 0);
  circle.AddLoops(100, 2 * kLap + 100, 21, 0);
  circle.AddLoops(kLap + 90, 2 * kLap + 90, 15, 0);
  circle.AddLoops(kLap + 120, 2 * kLap + 120, 5, 0);
  std::vector<int> group;
  for (int k = 112; k <= 116; ++k) {
    group.push_back(circle.AddShiftedLoop(kLap + k, 2 * kLap + k, 1.5));
  }
  circle.ExpectRefusedByTheMap(group);
}

TEST(MapVerifier, EveryLinkOfAnAcceptedClusterFitsTheMap) {
  // As above, but C has twelve true links at 100-111, whose ends are all
  // tied, and F at 112 is 0.95 m to the side. Alone with the odometry F
  // bends two soft steps and a link and fits; in the map only one step gives
  // way, and F's d²_l is over the one-link gate while Δ of all thirteen
  // links is under theirs: F is dropped, the rest accepted.
  Circle circle(3, 100.0);
  circle.AddLoops(100, kLap + 100, 20, 0);
  circle.AddLoops(100, 2 * kLap + 100, 12, 0);
  circle.AddLoops(kLap + 100, 2 * kLap + 100, 12, 0);
  const int f = circle.AddShiftedLoop(kLap + 112, 2 * kLap + 112, 0.95);
  circle.ExpectRefusedByTheMap({f});
}

TEST(MapVerifier, APosterioriScaleFollowsTheInformationMatrices) {
  // Information k times larger with gates k times looser: the same decisions
  // and map, each error k times larger.
  const auto graph = testing::NoisyChain<Pose2>(
      400, {{10, 136}, {12, 138}, {140, 266}, {150, 276}, {270, 396}}, 0.02);
  const PoseGraph<Pose2> scaled = testing::WithEachEdge(
      graph, [](Constraint<Pose2>* e, bool) { e->information *= 4.0; });
  RrrOptions options;
  options.noise_scale = 1.0;
  MapVerifierStats given, fourfold;
  const Verdict a = VerifyWithMap<Pose2>(graph, options, nullptr, &given);
  options.noise_scale = 4.0;
  const Verdict b = VerifyWithMap<Pose2>(scaled, options, nullptr, &fourfold);
  EXPECT_EQ(a.accepted, b.accepted);
  ASSERT_EQ(a.accepted.size(), 5u);
  EXPECT_EQ(fourfold.noise_scale, 4.0);  // a set scale is every gate's
  EXPECT_EQ(fourfold.group_noise_scale, 4.0);
  EXPECT_GT(given.a_posteriori_scale, 0.0);
  EXPECT_LT(given.a_posteriori_scale, 3.0);
  EXPECT_NEAR(fourfold.a_posteriori_scale, 4.0 * given.a_posteriori_scale,
              1e-6 * fourfold.a_posteriori_scale);
}

TEST(MapVerifier, LoopsThatUndoTheWayTravelledDoNotSetTheScale) {
  // Three revisits of ten links each, on a chain whose information
  // matrices are 100 times too small, and 900 loops that join poses 20 to 39
  // apart measured as the identity (a front-end matching the road just
  // driven): each departs from the odometry by about the way travelled
  // between its ends. At 30:1 their errors would hold the loops' low
  // quantile; they sample no noise, so the gates are the revisits' alone.
  std::vector<std::pair<int, int>> revisits;
  for (int r = 0; r < 3; ++r) {
    for (int k = 0; k < 10; ++k) {
      revisits.emplace_back(100 + 200 * r + k, 226 + 200 * r + k);
    }
  }
  const PoseGraph<Pose2> loose = testing::WithEachEdge(
      testing::NoisyChain<Pose2>(800, revisits, 0.01),
      [](Constraint<Pose2>* e, bool) { e->information *= 0.01; });
  PoseGraph<Pose2> spoiled = loose;
  const auto junk_info = loose.loops()[0].information;
  for (int k = 0; k < 900; ++k) {
    const int from = k % 740;
    const int to = from + 20 + (k / 740) * 13 + k % 7;  // each pair once
    spoiled.AddEdge({from, to, Pose2(), junk_info});
  }
  MapVerifierStats alone, among_junk;
  const Verdict revisits_alone =
      VerifyWithMap<Pose2>(loose, RrrOptions(), nullptr, &alone);
  const Verdict with_junk =
      VerifyWithMap<Pose2>(spoiled, RrrOptions(), nullptr, &among_junk);
  EXPECT_EQ(among_junk.noise_scale, alone.noise_scale);
  EXPECT_LT(among_junk.noise_scale, 1.0);
  EXPECT_EQ(with_junk.accepted, revisits_alone.accepted);
  EXPECT_GE(with_junk.accepted.size(), 27u);
}

TEST(MapVerifier, KeepsRevisitsThatCloseDriftTheOdometryUnderstates) {
  // The grid world with 40 false loops, its odometry turned by 0.0005 rad
  // a step more than measured (a bias its information does not model: a
  // long stretch drifts far beyond its covariance, a short one does not)
  // and its loops' information 25 times smaller than their noise. Against
  // the map, where the drift is taken out, the accepted clusters' errors
  // are far below those of single loops against the odometry; revisits
  // that close a long stretch are held to the single loops' scale.
  const SimulatedWorld world = World(2000, 40, 1, 3);
  const PoseGraph<Pose2> biased =
      testing::WithEachEdge(world.graph, [](Constraint<Pose2>* e, bool loop) {
        if (loop) {
          e->information *= 0.04;
        } else {
          e->measurement = e->measurement * Pose2(0.0, 0.0, 0.0005);
        }
      });
  MapVerifierStats stats;
  const Verdict verdict =
      VerifyWithMap<Pose2>(biased, RrrOptions(), nullptr, &stats);
  const std::set<int> wrong(world.false_loops.begin(), world.false_loops.end());
  size_t true_accepted = 0;
  for (const int k : verdict.accepted) {
    EXPECT_EQ(wrong.count(k), 0u) << "false loop " << k << " accepted";
    true_accepted += wrong.count(k) == 0 ? 1 : 0;
  }
  const size_t true_loops = biased.loops().size() - wrong.size();
  EXPECT_GE(true_accepted, 0.95 * true_loops) << true_loops << " true loops";
  EXPECT_EQ(stats.noise_scale_source, "clusters");
  // The groups' scale is the single loops', above the clusters'.
  EXPECT_GT(stats.group_noise_scale, stats.noise_scale);
}

TEST(MapVerifier, KeepsTheOneRevisitOfARingAmongTenTimesAsManyFalseLoops) {
  // A ring driven once around and on past its start: every true loop
  // closes the one place where the laps overlap, so no other revisit
  // vouches for it, and 500 false loops (nearly ten to each true one) are
  // spread over the whole run.
  WorldOptions options;
  options.layout = Layout::kRing;
  options.ring = 500;
  options.poses = 600;
  options.false_loops = 500;
  const SimulatedWorld world = SimulateWorld(options);
  const std::set<int> wrong(world.false_loops.begin(), world.false_loops.end());
  const size_t true_loops = world.graph.loops().size() - wrong.size();
  ASSERT_GE(true_loops, 45u);
  ASSERT_LE(true_loops, 55u);
  const Verdict verdict = VerifyWithMap(world.graph, RrrOptions());
  size_t true_accepted = 0;
  for (const int k : verdict.accepted) {
    EXPECT_EQ(wrong.count(k), 0u) << "false loop " << k << " accepted";
    true_accepted += wrong.count(k) == 0 ? 1 : 0;
  }
  EXPECT_GE(true_accepted, 0.98 * true_loops) << true_loops << " true loops";
}

TEST(MapVerifier, InformationTooLooseDecidesAsGiven) {
  // Every information matrix 100 and 10,000 times too small: the estimated
  // scale follows them, so the decisions are those of the graph as given.
  const SimulatedWorld world = World(1500, 60, 3, 2);
  const Verdict given = VerifyWithMap(world.graph, RrrOptions());
  ASSERT_GT(given.accepted.size(), 100u);
  for (const double factor : {1e-2, 1e-4}) {
    SCOPED_TRACE(factor);
    const PoseGraph<Pose2> loose = testing::WithEachEdge(
        world.graph,
        [factor](Constraint<Pose2>* e, bool) { e->information *= factor; });
    EXPECT_EQ(VerifyWithMap(loose, RrrOptions()).accepted, given.accepted);
  }
}

TEST(MapVerifier, RejectsAFalseLoopIn3D) {
  const auto graph = testing::ChainWithOneFalseLoop<Pose3>();
  const Verdict verdict = VerifyWithMap(graph, RrrOptions());
  EXPECT_EQ(verdict.accepted, (std::vector<int>{0, 1, 2, 3, 4}));
  EXPECT_EQ(verdict.rejected, (std::vector<int>{5}));
}

}  // namespace
}  // namespace rrr
