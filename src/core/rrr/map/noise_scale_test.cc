#include "rrr/rrr/map/noise_scale.h"

#include <gtest/gtest.h>

#include <random>

namespace rrr {
namespace {

// χ²_e samples times `scale`.
std::vector<double> ScaledChiSquare(int n, int e, double scale, unsigned seed) {
  std::mt19937 rng(seed);
  std::chi_squared_distribution<double> chi2(e);
  std::vector<double> out;
  for (int k = 0; k < n; ++k) out.push_back(scale * chi2(rng));
  return out;
}

TEST(NoiseScaleEstimate, FromLoopsRecoversASmallScale) {
  NoiseScaleEstimate estimate(3);
  EXPECT_EQ(estimate.FromLoops(), 1.0);  // nothing seen: as given
  for (const double v : ScaledChiSquare(4000, 3, 0.02, 1)) {
    estimate.AddLoopSample(v);
  }
  EXPECT_NEAR(estimate.FromLoops(), 0.02, 0.004);
}

TEST(NoiseScaleEstimate, FromLoopsHoldsWhenMostLoopsAreFalse) {
  NoiseScaleEstimate estimate(3);
  // 20 % true loops at scale 0.02, 80 % false ones a thousand times worse.
  for (const double v : ScaledChiSquare(800, 3, 0.02, 2)) {
    estimate.AddLoopSample(v);
  }
  for (const double v : ScaledChiSquare(3200, 3, 20.0, 3)) {
    estimate.AddLoopSample(v);
  }
  EXPECT_GT(estimate.FromLoops(), 0.005);
  EXPECT_LT(estimate.FromLoops(), 0.2);
}

TEST(NoiseScaleEstimate, FromLoopsNeverExceedsOne) {
  NoiseScaleEstimate estimate(6);
  for (const double v : ScaledChiSquare(100, 6, 40.0, 4)) {
    estimate.AddLoopSample(v);
  }
  EXPECT_EQ(estimate.FromLoops(), 1.0);
}

TEST(NoiseScaleEstimate, AcceptedClustersTakeOverAndAMinorityCannotMoveIt) {
  NoiseScaleEstimate estimate(3);
  for (int c = 0; c < NoiseScaleEstimate::kMinClusters - 1; ++c) {
    estimate.SetClusterSample(c, 0.5 * 6, 6);
  }
  EXPECT_EQ(estimate.Source(), "loops");
  EXPECT_EQ(estimate.Value(0.1), 0.1);
  for (int c = NoiseScaleEstimate::kMinClusters - 1; c < 30; ++c) {
    estimate.SetClusterSample(c, 0.5 * 6, 6);
  }
  EXPECT_EQ(estimate.Source(), "clusters");
  EXPECT_DOUBLE_EQ(estimate.Value(0.1), 0.5);
  for (int c = 30; c < 40; ++c) estimate.SetClusterSample(c, 1e4, 6);
  EXPECT_DOUBLE_EQ(estimate.Value(0.1), 0.5);
  // Clusters leaving the map leave the estimate.
  for (int c = 0; c < 30; ++c) estimate.RemoveClusterSample(c);
  EXPECT_EQ(estimate.Source(), "clusters");
  EXPECT_GT(estimate.Value(0.1), 1000.0);
}

TEST(NoiseScaleEstimate, TheClustersEstimateStaysInForceOnceItTookOver) {
  // Clusters that leave the map after the estimate took over must not bring
  // back the loops' estimate (looser here) that the first decisions used.
  NoiseScaleEstimate estimate(3);
  const int n = NoiseScaleEstimate::kMinClusters;
  for (int c = 0; c < n; ++c) estimate.SetClusterSample(c, 0.2 * 6, 6);
  ASSERT_EQ(estimate.Source(), "clusters");
  for (int c = 0; c < n - 1; ++c) estimate.RemoveClusterSample(c);
  EXPECT_EQ(estimate.Source(), "clusters");
  EXPECT_DOUBLE_EQ(estimate.Value(0.9), 0.2);
  estimate.RemoveClusterSample(n - 1);
  EXPECT_EQ(estimate.Source(), "loops");
  EXPECT_DOUBLE_EQ(estimate.Value(0.9), 0.9);
}

TEST(NoiseScaleEstimate, SetClusterSamplesReplacesTheSamplesOfThoseClusters) {
  NoiseScaleEstimate estimate(3);
  for (int c = 0; c < 25; ++c) estimate.SetClusterSample(c, 5.0 * 6, 6);
  EXPECT_DOUBLE_EQ(estimate.Value(1.0), 5.0);
  // Twenty of them at the minimized map; the other five keep theirs.
  std::vector<NoiseScaleEstimate::ClusterSample> at_minimum;
  for (int c = 0; c < 20; ++c) at_minimum.push_back({c, 0.5 * 3, 3});
  estimate.SetClusterSamples(at_minimum);
  EXPECT_DOUBLE_EQ(estimate.Value(1.0), 0.5);
  for (int c = 0; c < 16; ++c) estimate.RemoveClusterSample(c);
  EXPECT_DOUBLE_EQ(estimate.Value(1.0), 5.0);  // 4 at 0.5, 5 at 5.0
}

TEST(NoiseScaleEstimate, SamplesAtTheMinimumCarryTheMapsErrorOverTheLoops) {
  NoiseScaleEstimate estimate(3);
  std::vector<NoiseScaleEstimate::ClusterSample> at_minimum;
  for (int c = 0; c < 10; ++c) at_minimum.push_back({c, 0.1 * 6, 6});
  // The loops hold 6 of the map's 24: each sample counts four times.
  estimate.SetClusterSamplesAtMinimum(at_minimum, 24.0);
  EXPECT_DOUBLE_EQ(estimate.Value(1.0), 0.4);
  // A map's error under the loops' own (not a minimum) never lowers them.
  estimate.SetClusterSamplesAtMinimum(at_minimum, 3.0);
  EXPECT_DOUBLE_EQ(estimate.Value(1.0), 0.1);
}

}  // namespace
}  // namespace rrr
