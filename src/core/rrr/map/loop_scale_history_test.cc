#include "rrr/rrr/map/loop_scale_history.h"

#include <gtest/gtest.h>

#include <random>

namespace rrr {
namespace {

TEST(LoopScaleHistory, HoldsEachPosesValueAndClampsBeyond) {
  LoopScaleHistory history;
  EXPECT_EQ(history.At(5), 1.0);  // nothing recorded: as given
  EXPECT_EQ(history.FirstWith(1), -1);
  history.ExtendTo(3, 1.0, 0);
  history.ExtendTo(5, 0.5, 30);
  history.ExtendTo(4, 0.1, 40);  // already recorded: nothing changes
  EXPECT_EQ(history.size(), 5);
  EXPECT_EQ(history.At(2), 1.0);
  EXPECT_EQ(history.At(3), 0.5);
  EXPECT_EQ(history.At(-1), 1.0);
  EXPECT_EQ(history.At(99), 0.5);
  EXPECT_EQ(history.FirstWith(30), 3);
  EXPECT_EQ(history.FirstWith(31), -1);
}

TEST(LoopScaleHistory, RecomputesFromAPoseWithLateSamples) {
  std::mt19937 rng(4);
  std::chi_squared_distribution<double> chi2(3);
  // 40 loops at scale 0.02 that arrived at poses 0..39, only recorded late.
  std::vector<std::pair<int, double>> samples;
  for (int k = 39; k >= 0; --k) samples.emplace_back(k, 0.02 * chi2(rng));
  LoopScaleHistory history;
  history.ExtendTo(50, 1.0, 0);
  history.RecomputeFrom(20, samples, 3);
  EXPECT_EQ(history.At(19), 1.0);  // before `pose`: kept
  EXPECT_EQ(history.FirstWith(21), 20);
  EXPECT_EQ(history.FirstWith(40), 39);
  // From pose 20 on, each entry is the estimate from the loops by then.
  NoiseScaleEstimate by_45(3);
  for (const auto& [arrival, d2] : samples) by_45.AddLoopSample(d2);
  EXPECT_DOUBLE_EQ(history.At(45), by_45.FromLoops());
  EXPECT_LT(history.At(45), 0.1);
}

}  // namespace
}  // namespace rrr
