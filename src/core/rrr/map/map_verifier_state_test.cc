// The map procedure's saved state: a verifier restored from it goes on to
// decide exactly as the one that saved it; states that do not fit are
// refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <functional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "../../testing/feed_poses.h"
#include "../../testing/noisy_chain.h"
#include "../../testing/small_ring.h"
#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/graph/odometry_chain.h"
#include "rrr/rrr/map/map_verifier.h"
#include "rrr/rrr/published/incremental_verifier.h"
#include "rrr/sim/simulated_world.h"

namespace rrr {

// Edits a verifier's members into what no run saves, so that a test can
// check how restoring such a state is refused.
class MapVerifierStatePeer {
 public:
  using Verifier = MapVerifier<Pose2>;
  using Status = Verifier::Status;
  static std::vector<Verifier::ClusterRecord>& records(Verifier* v) {
    return v->records_;
  }
  static std::vector<DecisionReason>& reasons(Verifier* v) {
    return v->reasons_;
  }
  static std::vector<int>& cluster_of_loop(Verifier* v) {
    return v->cluster_of_loop_;
  }
  static int& judged_until(Verifier* v) { return v->judged_until_; }
  static const std::vector<Cluster>& clusters(const Verifier& v) {
    return v.clustering_.clusters();
  }
  // Builds the clustering again, cluster by cluster, each from the loops
  // `edit` leaves in its list, in that order (closed once built). Throws
  // std::logic_error if a loop no longer joins its cluster.
  static void Recluster(
      Verifier* v, const std::function<void(int, std::vector<int>*)>& edit) {
    Clustering rebuilt(v->options_.cluster_window);
    const PoseGraph<Pose2>& graph = v->graph();
    for (int c = 0; c < v->num_clusters(); ++c) {
      std::vector<int> loops = v->clustering_.clusters()[c].loops;
      edit(c, &loops);
      for (const int loop : loops) {
        const auto& e = graph.loops()[loop];
        if (rebuilt.Add(loop, graph.ids()[e.from], graph.ids()[e.to]) != c) {
          throw std::logic_error("loop " + std::to_string(loop) +
                                 " leaves cluster " + std::to_string(c));
        }
      }
      rebuilt.Close(c);
    }
    v->clustering_ = rebuilt;
  }
  // The first cluster with `status` and the first of its loops (-1, -1 if
  // none).
  static std::pair<int, int> FirstWith(const Verifier& v, Status status) {
    for (size_t c = 0; c < v.records_.size(); ++c) {
      if (v.records_[c].status == status) {
        return {static_cast<int>(c), v.clustering_.clusters()[c].loops[0]};
      }
    }
    return {-1, -1};
  }
};

namespace {

template <class Pose>
bool SameBits(const std::vector<Pose>& a, const std::vector<Pose>& b) {
  if (a.size() != b.size()) return false;
  for (size_t k = 0; k < a.size(); ++k) {
    const typename Pose::Parts pa = a[k].parts(), pb = b[k].parts();
    // Bit for bit, as the state promises (0.0 and -0.0 differ here).
    // NOLINTNEXTLINE(bugprone-suspicious-memory-comparison)
    if (std::memcmp(pa.data(), pb.data(), sizeof(pa)) != 0) return false;
  }
  return true;
}

// Runs one verifier through `graph` with an update every `every` poses, and
// another that is given the inputs up to pose `cut` with no update, restores
// the first one's state saved there, and goes on the same way. Expects every
// decision, the map's estimates bit for bit and the counters to be equal.
template <class Pose>
void ExpectRestoredVerifierDecidesAlike(const PoseGraph<Pose>& graph, int cut,
                                        int every) {
  const RrrOptions options;
  MapVerifier<Pose> original(options), restored(options);
  std::string state;
  const auto update_every = [&](MapVerifier<Pose>* v) {
    return [&, v](int p) {
      if ((p + 1) % every == 0) v->Update();
    };
  };
  testing::FeedPoses<Pose>(graph, 0, cut, &original, update_every(&original));
  state = original.SaveState();
  ASSERT_FALSE(state.empty());
  testing::FeedPoses<Pose>(graph, 0, cut, &restored, nullptr);
  ASSERT_TRUE(restored.SavedUnderSameOptions(state));
  restored.RestoreState(state);
  const std::string again = restored.SaveState();
  EXPECT_TRUE(again == state)
      << "the restored state differs from byte "
      << std::mismatch(again.begin(), again.end(), state.begin(), state.end())
                 .first -
             again.begin()
      << " of " << state.size();
  testing::FeedPoses<Pose>(graph, cut, graph.num_poses(), &original,
                           update_every(&original));
  testing::FeedPoses<Pose>(graph, cut, graph.num_poses(), &restored,
                           update_every(&restored));
  original.Finish();
  restored.Finish();
  int accepted = 0;
  for (int c = 0; c < original.num_candidates(); ++c) {
    EXPECT_EQ(restored.state(c), original.state(c)) << "candidate " << c;
    accepted += original.state(c) == LoopState::kAccepted;
  }
  EXPECT_GT(accepted, 0);
  EXPECT_TRUE(SameBits(restored.Map(), original.Map()));
  EXPECT_EQ(restored.noise_scale(), original.noise_scale());
  EXPECT_EQ(restored.num_solves(), original.num_solves());
  EXPECT_EQ(restored.stats().trials, original.stats().trials);
}

SimulatedWorld GroupedWorld() {
  WorldOptions world;
  world.poses = 1500;
  world.false_loops = 40;
  world.group = 3;
  return SimulateWorld(world);
}

TEST(MapVerifierState, ARestoredVerifierDecidesAsTheOneThatSavedIt) {
  const SimulatedWorld w = GroupedWorld();
  // Cut where clusters are pending, accepted and rejected, with updates
  // after every pose and every 13.
  for (const int cut : {400, 900}) {
    for (const int every : {1, 13}) {
      SCOPED_TRACE("cut " + std::to_string(cut) + ", every " +
                   std::to_string(every));
      ExpectRestoredVerifierDecidesAlike(w.graph, cut, every);
    }
  }
}

TEST(MapVerifierState, ARestoredVerifierDecidesAsTheOneThatSavedItIn3D) {
  const auto graph = testing::ChainWithOneFalseLoop<Pose3>();
  ExpectRestoredVerifierDecidesAlike(graph, 450, 7);
}

// The state of a verifier with the default options after the first 600
// poses of GroupedWorld(), updated after each; gives `other` the same inputs
// without an update.
std::string DefaultStateWithInputsTo(MapVerifier<Pose2>* other) {
  const SimulatedWorld w = GroupedWorld();
  MapVerifier<Pose2> saver{RrrOptions()};
  testing::FeedPoses<Pose2>(w.graph, 0, 600, &saver,
                            [&](int) { saver.Update(); });
  testing::FeedPoses<Pose2>(w.graph, 0, 600, other, nullptr);
  return saver.SaveState();
}

TEST(MapVerifierState, OptionsOfThePublishedProcedureAloneDoNotCount) {
  RrrOptions other;
  other.iterations = 7;
  other.steps = SolveSteps::kTrustRegion;
  other.span_gate = true;
  MapVerifier<Pose2> verifier(other);
  const std::string state = DefaultStateWithInputsTo(&verifier);
  EXPECT_TRUE(verifier.SavedUnderSameOptions(state));
  verifier.RestoreState(state);
  EXPECT_EQ(verifier.SaveState(), state);
}

TEST(MapVerifierState, AStateOfOtherOptionsIsNotRestored) {
  RrrOptions other;
  other.noise_margin = 4.0;
  MapVerifier<Pose2> verifier(other);
  const std::string state = DefaultStateWithInputsTo(&verifier);
  EXPECT_FALSE(verifier.SavedUnderSameOptions(state));
  EXPECT_THROW(verifier.RestoreState(state), std::runtime_error);
}

TEST(MapVerifierState, AStateOfAnEarlierRuleIsNotRestored) {
  // A checkpoint that an earlier version of the procedure wrote holds
  // another rule's decisions: the session's updates run again instead.
  ByteWriter earlier;
  earlier.Text("rrr map procedure state, version 1");
  earlier.Text("its options");
  MapVerifier<Pose2> verifier{RrrOptions()};
  EXPECT_FALSE(verifier.SavedUnderSameOptions(earlier.bytes()));
  ByteWriter other;
  other.Text("some other state");
  EXPECT_THROW(verifier.SavedUnderSameOptions(other.bytes()),
               std::runtime_error);
}

TEST(MapVerifierState, AStateOfOtherInputsOrCutShortIsRefusedNamingWhy) {
  const SimulatedWorld w = GroupedWorld();
  MapVerifier<Pose2> saver{RrrOptions()};
  testing::FeedPoses<Pose2>(w.graph, 0, 600, &saver,
                            [&](int) { saver.Update(); });
  const std::string state = saver.SaveState();
  const auto refusal = [&](int poses, const std::string& bytes) {
    MapVerifier<Pose2> verifier{RrrOptions()};
    testing::FeedPoses<Pose2>(w.graph, 0, poses, &verifier, nullptr);
    try {
      verifier.RestoreState(bytes);
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("restored");
  };
  EXPECT_NE(refusal(601, state).find("saved with 600 poses"), std::string::npos)
      << refusal(601, state);
  const std::string half = refusal(600, state.substr(0, state.size() / 2));
  EXPECT_TRUE(half.find("ends before") != std::string::npos ||
              half.find("does not fit") != std::string::npos)
      << half;
  EXPECT_NE(refusal(600, "not a state").find("the format"), std::string::npos);
  EXPECT_NE(refusal(600, state + "x").find("past its end"), std::string::npos);
}

TEST(MapVerifierState, AStateThatContradictsItselfIsRefusedNamingWhat) {
  // What a fault in a writer or a damaged database could hold: members
  // that each read back but do not fit the rest of the state.
  using Peer = MapVerifierStatePeer;
  using Status = Peer::Status;
  using Verifier = Peer::Verifier;
  constexpr int kPoses = 600;
  const SimulatedWorld w = GroupedWorld();
  Verifier saver{RrrOptions()};
  testing::FeedPoses<Pose2>(w.graph, 0, kPoses, &saver,
                            [&](int) { saver.Update(); });
  const std::string state = saver.SaveState();
  const std::pair<int, int> first_accepted =
      Peer::FirstWith(saver, Status::kAccepted);
  const std::pair<int, int> first_refused =
      Peer::FirstWith(saver, Status::kRefused);
  const int accepted = first_accepted.first;
  const int accepted_loop = first_accepted.second;
  const int refused = first_refused.first;
  const int refused_loop = first_refused.second;
  ASSERT_GE(accepted, 0);
  ASSERT_GE(refused, 0);
  const int clusters = saver.num_clusters();
  // What restoring the state says once `edit` changed it.
  const auto refusal = [&](const std::function<void(Verifier*)>& edit) {
    Verifier edited{RrrOptions()}, verifier{RrrOptions()};
    testing::FeedPoses<Pose2>(w.graph, 0, kPoses, &edited);
    testing::FeedPoses<Pose2>(w.graph, 0, kPoses, &verifier);
    edited.RestoreState(state);
    edit(&edited);
    try {
      verifier.RestoreState(edited.SaveState());
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("restored");
  };
  const auto expect_refusal = [&](const std::function<void(Verifier*)>& edit,
                                  const std::string& named) {
    const std::string said = refusal(edit);
    EXPECT_NE(said.find(named), std::string::npos)
        << "expected \"" << named << "\", got \"" << said << "\"";
  };
  EXPECT_EQ(refusal([](Verifier*) {}), "restored");
  const std::string n = std::to_string(clusters);
  expect_refusal(
      [&](Verifier* v) {
        Peer::records(v)[accepted].status = Status::kRefused;
      },
      "cluster " + std::to_string(accepted) + " has " +
          std::to_string(Peer::records(&saver)[accepted].accepted.size()) +
          " links in the map and another status");
  expect_refusal(
      [&](Verifier* v) {
        Peer::records(v)[refused].status = Status::kAccepted;
      },
      "cluster " + std::to_string(refused) +
          " has 0 links in the map and another status");
  expect_refusal(
      [&](Verifier* v) { Peer::cluster_of_loop(v)[accepted_loop] = refused; },
      "cluster " + std::to_string(accepted) + " names loop " +
          std::to_string(accepted_loop) + " of another cluster");
  expect_refusal(
      [&](Verifier* v) { Peer::cluster_of_loop(v)[refused_loop] = -1; },
      "a loop's cluster is -1, outside 0.." + std::to_string(clusters - 1));
  expect_refusal(
      [&](Verifier* v) { Peer::records(v)[refused].ready_pose = kPoses; },
      "a cluster's ready pose is 600, outside -1..599");
  expect_refusal(
      [&](Verifier* v) {
        Peer::reasons(v)[refused_loop].by_cluster = clusters;
      },
      "the cluster that outweighed a link is " + n + ", outside -1..");
  expect_refusal([&](Verifier* v) { Peer::reasons(v)[accepted_loop].dof = -1; },
                 "a decision's degrees of freedom is -1, outside 0..");
  expect_refusal([&](Verifier* v) { Peer::judged_until(v) = kPoses; },
                 "the pose judged until is 600, outside -1..599");
  expect_refusal([&](Verifier* v) { Peer::records(v).pop_back(); },
                 "the state has " + std::to_string(clusters - 1) +
                     " cluster records for " + n + " clusters");
  // Edits of the clustering: a cluster of several loops with its first two
  // swapped, and an accepted cluster of several links without its last
  // loop, accepted, which the map still holds.
  int several = -1, without_last = -1, in_map = 0;
  for (int c = 0; c < clusters; ++c) {
    const std::vector<int>& loops = Peer::clusters(saver)[c].loops;
    const std::vector<int>& accepted = Peer::records(&saver)[c].accepted;
    in_map += static_cast<int>(accepted.size());
    if (several < 0 && loops.size() > 1) several = c;
    if (without_last < 0 && accepted.size() > 1 &&
        accepted.back() == loops.back()) {
      without_last = c;
    }
  }
  ASSERT_GE(several, 0);
  ASSERT_GE(without_last, 0);
  const std::vector<int>& in_order = Peer::clusters(saver)[several].loops;
  expect_refusal(
      [&](Verifier* v) {
        Peer::Recluster(v, [&](int c, std::vector<int>* loops) {
          if (c == several) std::swap((*loops)[0], (*loops)[1]);
        });
      },
      "a cluster's loop (they ascend) is " + std::to_string(in_order[0]) +
          ", outside " + std::to_string(in_order[1] + 1) + "..");
  expect_refusal(
      [&](Verifier* v) {
        Peer::Recluster(v, [&](int c, std::vector<int>* loops) {
          if (c == without_last) loops->pop_back();
        });
      },
      "the map holds " + std::to_string(in_map) + " loops, the clusters " +
          std::to_string(in_map - 1));
}

TEST(MapVerifierState, AStateWithAByteChangedIsRefusedOrFinishes) {
  // A checkpoint read back from a damaged database: one byte of a state in
  // turn (every 7th) set to 0xff, which makes a count, an index or a pose
  // negative or far too large. Each is refused with std::runtime_error, or
  // restores into a verifier that finishes and saves its state again.
  const SimulatedWorld& w = testing::SmallRing();
  constexpr int kSaved = testing::kSmallRingSavedPoses;
  MapVerifier<Pose2> saver{RrrOptions()};
  testing::FeedPoses<Pose2>(w.graph, 0, kSaved, &saver,
                            [&](int) { saver.Update(); });
  const std::string state = saver.SaveState();
  int refused = 0, restored = 0;
  for (size_t at = 0; at < state.size(); at += 7) {
    std::string damaged = state;
    damaged[at] = static_cast<char>(0xff);
    MapVerifier<Pose2> verifier{RrrOptions()};
    testing::FeedPoses<Pose2>(w.graph, 0, kSaved, &verifier);
    try {
      verifier.RestoreState(damaged);
    } catch (const std::runtime_error&) {
      ++refused;
      continue;
    }
    ++restored;
    EXPECT_NO_THROW(verifier.Finish()) << "byte " << at;
    EXPECT_NO_THROW(verifier.SaveState()) << "byte " << at;
  }
  EXPECT_GT(refused, 0);
  EXPECT_GT(restored, 0);
}

TEST(MapVerifierState, ThePublishedProcedureSavesNoState) {
  IncrementalVerifier<Pose2> verifier{RrrOptions()};
  EXPECT_EQ(verifier.SaveState(), "");
  EXPECT_THROW(verifier.SavedUnderSameOptions("anything"), std::runtime_error);
  EXPECT_THROW(verifier.RestoreState("anything"), std::logic_error);
}

}  // namespace
}  // namespace rrr
