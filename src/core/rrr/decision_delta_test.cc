// DecisionDelta: the changes it carries add up to every candidate's state.
#include "rrr/rrr/decision_delta.h"

#include <gtest/gtest.h>

#include <map>

#include "../testing/chain_worlds.h"
#include "rrr/geometry/pose2.h"
#include "rrr/rrr/map/map_verifier.h"
#include "rrr/rrr/published/incremental_verifier.h"
#include "rrr/sim/simulated_world.h"

namespace rrr {
namespace {

// What a consumer knows of a candidate.
struct Known {
  LoopState state;
  int cluster;
  bool waiting;
  bool operator==(const Known& o) const {
    return state == o.state && cluster == o.cluster && waiting == o.waiting;
  }
};
using Table = std::map<int, Known>;

Known Now(const OnlineVerifier<Pose2>& v, int c) {
  return {v.state(c), v.cluster_of(c), v.waiting(c)};
}

void Carry(const OnlineVerifier<Pose2>& v, const std::vector<int>& carried,
           Table* table) {
  for (const int c : carried) (*table)[c] = Now(v, c);
}

// Feeds a spoiled world to `v` pose by pose, carrying what `delta` says
// after each update, and checks the table against the verifier at the end;
// returns the candidates carried over the run.
size_t FeedAndCompare(int poses, OnlineVerifier<Pose2>* verifier) {
  WorldOptions world;
  world.poses = poses;
  world.false_loops = 30;
  world.group = 3;
  const SimulatedWorld w = SimulateWorld(world);
  const OnlineVerifier<Pose2>& v = *verifier;
  DecisionDelta delta;
  Table table;
  size_t carried_total = 0;
  int quiet_updates = 0, reclusterings = 0, clustered = 0;
  FeedInArrivalOrder<Pose2>(
      w.graph, verifier, 1, [&](const std::vector<DecisionChange>& changes) {
        const int known = static_cast<int>(table.size());
        const std::vector<int> carried = delta.Next(v, changes);
        carried_total += carried.size();
        Carry(v, carried, &table);
        // Nothing changed, nothing new, nothing clustered (again): nothing
        // is carried.
        const bool reclustered = v.num_reclusterings() != reclusterings;
        reclusterings = v.num_reclusterings();
        int now_clustered = 0;
        for (int c = 0; c < v.num_candidates(); ++c) {
          now_clustered += v.cluster_of(c) >= 0;
        }
        const bool newly_clustered = now_clustered != clustered;
        clustered = now_clustered;
        if (changes.empty() && v.num_candidates() == known && !reclustered &&
            !newly_clustered) {
          ++quiet_updates;
          EXPECT_TRUE(carried.empty());
        }
      });
  EXPECT_EQ(table.size(), static_cast<size_t>(v.num_candidates()));
  int accepted = 0;
  for (int c = 0; c < v.num_candidates(); ++c) {
    EXPECT_TRUE(table.count(c) && table.at(c) == Now(v, c))
        << "candidate " << c;
    accepted += v.state(c) == LoopState::kAccepted;
  }
  EXPECT_GT(accepted, 0);
  EXPECT_GT(quiet_updates, 100);
  return carried_total;
}

TEST(DecisionDelta, WhatItCarriesAddsUpToEveryStateAndCluster) {
  RrrOptions options;
  MapVerifier<Pose2> v(options);
  const size_t carried = FeedAndCompare(800, &v);
  // Each candidate is carried when new, when clustered and when it
  // changes, not at every update.
  EXPECT_LT(carried, 4u * static_cast<size_t>(v.num_candidates()));
  EXPECT_EQ(v.num_reclusterings(), 0);
}

TEST(DecisionDelta, FollowsThePublishedProcedureAsItClustersAgain) {
  RrrOptions options;
  options.procedure = Procedure::kPublished;
  IncrementalVerifier<Pose2> v(options);
  FeedAndCompare(400, &v);
  EXPECT_GT(v.num_reclusterings(), 0);
}

TEST(DecisionDelta, CarriesACandidateAgainWhenItStopsWaiting) {
  RrrOptions options;
  MapVerifier<Pose2> v(options);
  DecisionDelta delta;
  const Pose2::Jacobian info = Pose2::Jacobian::Identity() * 100;
  v.AddFirstPose(0, Pose2());
  v.AddOdometry(Pose2(1, 0, 0), info);
  v.AddOdometry(Pose2(1, 0, 0), info);
  const int c = v.AddLoop(6, 0, Pose2(-6, 0, 0), info);
  EXPECT_EQ(delta.Next(v, {}), std::vector<int>{c});  // new, waiting
  EXPECT_TRUE(delta.Next(v, {}).empty());
  v.AddOdometry(Pose2(1, 0, 0), info);
  EXPECT_TRUE(delta.Next(v, {}).empty());  // still waiting
  for (int k = 0; k < 3; ++k) v.AddOdometry(Pose2(1, 0, 0), info);
  ASSERT_GE(v.loop_of(c), 0);
  EXPECT_EQ(delta.Next(v, {}), std::vector<int>{c});  // in the graph now
  EXPECT_TRUE(delta.Next(v, {}).empty());
  // The map procedure takes a pose's candidates in once the next pose
  // exists.
  v.AddOdometry(Pose2(1, 0, 0), info);
  const std::vector<DecisionChange> changes = v.Update();
  ASSERT_GE(v.cluster_of(c), 0);
  EXPECT_EQ(delta.Next(v, changes), std::vector<int>{c});  // clustered
  EXPECT_TRUE(delta.Next(v, {}).empty());
}

TEST(DecisionDelta, FollowsCandidatesWithinAndBetweenChains) {
  RrrOptions options;
  MapVerifier<Pose2> v(options);
  DecisionDelta delta;
  const Pose2::Jacobian info = Pose2::Jacobian::Identity() * 100;
  const int a = v.AddChain(0, Pose2());
  const int b = v.AddChain(100, Pose2(0, 5, 0));
  v.AddOdometry(a, Pose2(1, 0, 0), info);
  // Ahead of chain a's poses, and between a and a pose of b not there yet.
  const int inside = v.AddLoop(4, 0, Pose2(-4, 0, 0), info);
  const int between = v.AddLoop(1, 102, Pose2(1, 5, 0), info);
  EXPECT_EQ(delta.Next(v, {}), (std::vector<int>{inside, between}));
  EXPECT_TRUE(delta.Next(v, {}).empty());
  for (int k = 0; k < 3; ++k) v.AddOdometry(a, Pose2(1, 0, 0), info);
  ASSERT_FALSE(v.waiting(inside));
  EXPECT_EQ(delta.Next(v, {}), std::vector<int>{inside});  // no longer waits
  v.AddOdometry(b, Pose2(1, 0, 0), info);
  EXPECT_TRUE(delta.Next(v, {}).empty());  // still waiting
  v.AddOdometry(b, Pose2(1, 0, 0), info);
  ASSERT_FALSE(v.waiting(between));
  EXPECT_EQ(delta.Next(v, {}), std::vector<int>{between});
  EXPECT_TRUE(delta.Next(v, {}).empty());
}

TEST(DecisionDelta, WhatItCarriesAddsUpOverTwoSessions) {
  size_t true_loops = 0;
  const PoseGraph<Pose2> graph = testing::TwoSessionsWithFalseLoops(
      SimulateWorld(testing::Grid(800, 5)), 400, &true_loops);
  MapVerifier<Pose2> v(testing::ChainWorldOptions());
  DecisionDelta delta;
  Table table;
  size_t carried_total = 0;
  const auto carry = [&](const std::vector<DecisionChange>& changes) {
    const std::vector<int> carried = delta.Next(v, changes);
    carried_total += carried.size();
    Carry(v, carried, &table);
  };
  FeedInArrivalOrder<Pose2>(graph, &v, 1, carry, 0, ArrivalOrder(graph, true));
  ASSERT_EQ(table.size(), static_cast<size_t>(v.num_candidates()));
  int accepted = 0;
  for (int c = 0; c < v.num_candidates(); ++c) {
    EXPECT_TRUE(table.at(c) == Now(v, c)) << "candidate " << c;
    accepted += v.state(c) == LoopState::kAccepted;
  }
  EXPECT_GT(accepted, 0);
  EXPECT_LT(carried_total, 4u * static_cast<size_t>(v.num_candidates()));
}

}  // namespace
}  // namespace rrr
