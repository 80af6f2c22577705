// The map procedure on shared datasets spoiled as `rrr spoil` spoils them,
// when the datasets are present (RRR_DATASETS, default ../shared/datasets
// beside the source tree): a set where a step of the procedure decides.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <string>
#include <variant>

#include "../testing/dataset_dir.h"
#include "rrr/eval/loop_scores.h"
#include "rrr/geometry/pose3.h"
#include "rrr/io/g2o.h"
#include "rrr/rrr/map_verifier.h"
#include "rrr/sim/false_loops.h"

namespace rrr {
namespace {

std::string SyntheticPath(const std::string& name) {
  return testing::DatasetDir() + "/synthetic/" + name + ".g2o";
}

// Spoils the 3D dataset at `path` with `false_loops` and scores the map
// procedure's decisions (cluster window 10, as the benchmarks run it).
LoopScores ScoreSpoiled3(const std::string& path,
                         const FalseLoopOptions& false_loops) {
  auto graph = std::get<PoseGraph<Pose3>>(ReadG2o(path).graph);
  const std::vector<int> added = AddFalseLoops(&graph, false_loops);
  RrrOptions options;
  options.cluster_window = 10;
  const Verdict verdict = VerifyWithMap(graph, options);
  std::vector<bool> accepted(graph.loops().size()),
      correct(graph.loops().size(), true);
  for (const int k : verdict.accepted) accepted[k] = true;
  for (const int k : added) correct[k] = false;
  return ScoreLoops(accepted, correct);
}

TEST(SpoiledDataset, JudgesAgainTheClustersAcceptedUnderALooserScale) {
  // sphere2500 with 1000 local false loops: the first decisions run under
  // the scale of single loops, which lets loops a few poses long through;
  // judged again once the clusters' estimate is at most half of it, they
  // go (precision 0.9984 without).
  const std::string path = SyntheticPath("sphere2500");
  if (!std::ifstream(path)) {
    GTEST_SKIP() << path
                 << " not found (set RRR_DATASETS to the datasets folder)";
  }
  FalseLoopOptions false_loops;
  false_loops.count = 1000;
  false_loops.local = true;
  false_loops.seed = 3;
  const LoopScores scores = ScoreSpoiled3(path, false_loops);
  EXPECT_EQ(scores.precision(), 1.0);
  EXPECT_GE(scores.recall(), 0.99);
}

}  // namespace
}  // namespace rrr
