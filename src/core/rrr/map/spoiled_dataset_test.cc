// The map procedure on shared datasets, as they are and spoiled as `rrr
// spoil` spoils them, when the datasets are present (RRR_DATASETS, default
// ../shared/datasets beside the source tree): sets where a step of the
// procedure decides.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "../../testing/dataset_dir.h"
#include "rrr/eval/loop_scores.h"
#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/graph/chain_spans.h"
#include "rrr/io/g2o.h"
#include "rrr/rrr/map/verify_with_map.h"
#include "rrr/sim/false_loops.h"
#include "rrr/solver/pose_graph_solver.h"

namespace rrr {
namespace {

std::string SyntheticPath(const std::string& name) {
  return testing::DatasetDir() + "/synthetic/" + name + ".g2o";
}

// The map procedure's decisions on `graph` (cluster window 10, as the
// benchmarks run it), scored against its false loops `added`.
template <class Pose>
LoopScores ScoreMapProcedure(const PoseGraph<Pose>& graph,
                             const std::vector<int>& added) {
  RrrOptions options;
  options.cluster_window = 10;
  const Verdict verdict = VerifyWithMap(graph, options);
  std::vector<bool> accepted(graph.loops().size()),
      correct(graph.loops().size(), true);
  for (const int k : verdict.accepted) accepted[k] = true;
  for (const int k : added) correct[k] = false;
  return ScoreLoops(accepted, correct);
}

// Spoils the dataset at `path` with `count` local false loops drawn with
// `seed` and scores the map procedure's decisions.
LoopScores ScoreLocallySpoiled(const std::string& path, int count,
                               std::uint64_t seed) {
  FalseLoopOptions false_loops;
  false_loops.count = count;
  false_loops.local = true;
  false_loops.seed = seed;
  return std::visit(
      [&](auto graph) {
        const std::vector<int> added = AddFalseLoops(&graph, false_loops);
        return ScoreMapProcedure(graph, added);
      },
      ReadG2o(path).graph);
}

// A dataset spoiled with 1000 local false loops where a step of the noise
// scale decides: no false loop may be accepted, nor more than 1 % of the
// true ones lost.
struct Case {
  const char* dataset;
  std::uint64_t seed;
};

class SpoiledDataset : public ::testing::TestWithParam<Case> {};

TEST_P(SpoiledDataset, AcceptsNoFalseLoop) {
  const std::string path = SyntheticPath(GetParam().dataset);
  if (!std::ifstream(path)) {
    GTEST_SKIP() << path
                 << " not found (set RRR_DATASETS to the datasets folder)";
  }
  const LoopScores scores = ScoreLocallySpoiled(path, 1000, GetParam().seed);
  EXPECT_EQ(scores.precision(), 1.0);
  EXPECT_GE(scores.recall(), 0.99);
}

INSTANTIATE_TEST_SUITE_P(
    WhereTheScaleDecides, SpoiledDataset,
    ::testing::Values(
        // The first decisions run under the scale of single loops, which
        // lets loops a few poses long through; judged again once the
        // clusters' estimate is at most half of it, and under it even when
        // clusters leave the map, they go (precision 0.9984 without
        // re-judging, 0.9992 when the scale falls back to the loops').
        Case{"sphere2500", 3},
        // (928, 931) spans an odometry step whose information claims σ
        // 0.42 m, and fits it under the scale of the local trials'
        // increases; under that of the accepted clusters' errors at the
        // minimized map it does not (precision 0.9989 without).
        Case{"intel", 1}),
    [](const auto& info) {
      return std::string(info.param.dataset) + "Seed" +
             std::to_string(info.param.seed);
    });

// The poses of `graph` with ids first..last (one chain) and the loops
// between them.
PoseGraph<Pose2> Stretch(const PoseGraph<Pose2>& graph, PoseId first,
                         PoseId last) {
  const ChainSpan span{graph.IndexOf(first), graph.IndexOf(last)};
  std::vector<int> inside;
  for (size_t k = 0; k < graph.loops().size(); ++k) {
    const auto& e = graph.loops()[k];
    if (span.Holds(e.from) && span.Holds(e.to)) {
      inside.push_back(static_cast<int>(k));
    }
  }
  return SubGraph(graph, {span}, graph.estimates(), inside);
}

// city10000's poses first..last plus `count` false loops in groups of ten
// (`rrr spoil --group 10 --seed seed`, bench/city_stretch.py), scored. On
// a stretch a self-consistent false group is often the first loop joining
// two streets, with nothing in the map yet to refute it.
LoopScores ScoreCityStretch(PoseId first, PoseId last, int count,
                            std::uint64_t seed) {
  PoseGraph<Pose2> graph = Stretch(
      std::get<PoseGraph<Pose2>>(ReadG2o(SyntheticPath("city10000")).graph),
      first, last);
  const std::vector<Pose2> optimum =
      PoseGraphSolver<Pose2>(graph, 1).Optimize(AllLoops(graph), {});
  FalseLoopOptions false_loops;
  false_loops.count = count;
  false_loops.group = 10;
  false_loops.seed = seed;
  const std::vector<int> added = AddFalseLoops(&graph, false_loops, &optimum);
  return ScoreMapProcedure(graph, added);
}

class StretchOfACity : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string path = SyntheticPath("city10000");
    if (!std::ifstream(path)) {
      GTEST_SKIP() << path
                   << " not found (set RRR_DATASETS to the datasets folder)";
    }
  }
};

// Poses 7500-9999 + 250: a false group is accepted first, the true
// revisits of those streets that come next are refused against the map it
// bent, and the arbiter later drops it. Those revisits come back once the
// map without the group fits them (recall 0.906 under an early rule that
// left them refused).
TEST_F(StretchOfACity, JudgesAgainTheRevisitsAFalseGroupHeldOut) {
  const LoopScores scores = ScoreCityStretch(7500, 9999, 250, 4);
  EXPECT_EQ(scores.precision(), 1.0);
  EXPECT_GE(scores.recall(), 0.98);
}

// Poses 0-2499 + 500: the revisit that fails against a false group's map
// strains the true clusters the group bent more than the group; setting
// those aside first used up the links the exchange may remove before the
// group was reached (precision 0.987, recall 0.760). Only clusters whose
// removal lowers the revisit's Δ are set aside.
TEST_F(StretchOfACity, SetsAsideOnlyTheClustersInTheConflict) {
  const LoopScores scores = ScoreCityStretch(0, 2499, 500, 4);
  EXPECT_EQ(scores.precision(), 1.0);
  EXPECT_GE(scores.recall(), 0.98);
}

// How many loops the map procedure (window 10) accepts of more/`name`.g2o,
// an outlier-free graph, and how many it has; nothing if the file is not
// there.
struct Kept {
  size_t accepted;
  size_t loops;
};
std::optional<Kept> KeptOfOutlierFree(const std::string& name) {
  const std::string path = testing::DatasetDir() + "/more/" + name + ".g2o";
  if (!std::ifstream(path)) return std::nullopt;
  return std::visit(
      [](const auto& graph) {
        RrrOptions options;
        options.cluster_window = 10;
        return Kept{VerifyWithMap(graph, options).accepted.size(),
                    graph.loops().size()};
      },
      ReadG2o(path).graph);
}

// KITTI's odometry drifts over a long stretch far beyond its covariances,
// while its loops agree with the map once the drift is closed: the
// revisits that close the longest drift are judged at the single loops'
// scale, and at least 98 % of the loops of 02 and 05 are kept (72 % and
// 59 % when the clusters' tighter estimate held them).
TEST(OutlierFreeDataset, KeepsTheLoopsThatCloseKittisDrift) {
  for (const char* name : {"kitti_02", "kitti_05"}) {
    const std::optional<Kept> kept = KeptOfOutlierFree(name);
    if (!kept) {
      GTEST_SKIP() << name << " not found in " << testing::DatasetDir()
                   << "/more (set RRR_DATASETS to the datasets folder)";
    }
    EXPECT_GE(kept->accepted, 0.98 * kept->loops) << name;
  }
}

// sphere_bignoise_vertex3 has no false loop, and its errors are far beyond
// its information (χ²/dof 185 at the optimum). The accepted clusters'
// errors settle the scale over many rounds of the arbiter, each taking back
// links refused under the scale before: stopped after three rounds, 4 of
// its 6,448 loops stayed refused (ATE 0.19 m). It keeps every loop.
TEST(OutlierFreeDataset, KeepsEveryLoopOfAGraphWhoseScaleSettlesSlowly) {
  const std::optional<Kept> kept = KeptOfOutlierFree("sphere_bignoise_vertex3");
  if (!kept) {
    GTEST_SKIP() << "sphere_bignoise_vertex3 not found in "
                 << testing::DatasetDir()
                 << "/more (set RRR_DATASETS to the datasets folder)";
  }
  EXPECT_EQ(kept->accepted, kept->loops);
}

}  // namespace
}  // namespace rrr
