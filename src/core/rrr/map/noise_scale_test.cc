#include "rrr/rrr/map/noise_scale.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <random>

namespace rrr {
namespace {

// χ²_e samples times `scale`.
std::vector<double> ScaledChiSquare(int n, int e, double scale, unsigned seed) {
  std::mt19937 rng(seed);
  std::chi_squared_distribution<double> chi2(e);
  std::vector<double> out(n);
  for (double& v : out) v = scale * chi2(rng);
  return out;
}

// Adds `chi2` as plausible loop samples that arrived at pose `arrival`.
void AddLoops(NoiseScaleEstimate* estimate, const std::vector<double>& chi2,
              int arrival = 0) {
  for (const double v : chi2) estimate->AddLoopSample(arrival, v, 0.0, 1.0);
}

TEST(NoiseScaleEstimate, ThePriorRecoversASmallScale) {
  NoiseScaleEstimate estimate(3);
  EXPECT_EQ(estimate.ValueAt(0), 1.0);  // nothing seen: as given
  AddLoops(&estimate, ScaledChiSquare(4000, 3, 0.02, 1));
  estimate.RecordUntil(1);
  EXPECT_NEAR(estimate.ValueAt(0), 0.02, 0.004);
  EXPECT_EQ(estimate.SourceAt(0), "loops");
}

TEST(NoiseScaleEstimate, ThePriorHoldsWhenMostLoopsAreFalse) {
  NoiseScaleEstimate estimate(3);
  // 20 % true loops at scale 0.02, 80 % false ones a thousand times worse.
  AddLoops(&estimate, ScaledChiSquare(800, 3, 0.02, 2));
  AddLoops(&estimate, ScaledChiSquare(3200, 3, 20.0, 3));
  estimate.RecordUntil(1);
  EXPECT_GT(estimate.ValueAt(0), 0.005);
  EXPECT_LT(estimate.ValueAt(0), 0.2);
}

TEST(NoiseScaleEstimate, ThePriorNeverExceedsOne) {
  NoiseScaleEstimate estimate(6);
  AddLoops(&estimate, ScaledChiSquare(100, 6, 40.0, 4));
  estimate.RecordUntil(1);
  EXPECT_EQ(estimate.ValueAt(0), 1.0);
}

TEST(NoiseScaleEstimate, LoopsThatUndoTheWayTravelledSampleNothing) {
  NoiseScaleEstimate estimate(3);
  // Each departs from the odometry by 0.9 of the way travelled.
  for (const double v : ScaledChiSquare(200, 3, 0.01, 5)) {
    estimate.AddLoopSample(0, v, 9.0, 10.0);
  }
  estimate.RecordUntil(1);
  EXPECT_EQ(estimate.ValueAt(0), 1.0);
  EXPECT_EQ(estimate.FirstPoseWithEnoughLoops(), -1);
}

TEST(NoiseScaleEstimate, EachPoseCountsTheLoopsThatArrivedByIt) {
  NoiseScaleEstimate estimate(3);
  AddLoops(&estimate, ScaledChiSquare(40, 3, 0.01, 6), 5);
  estimate.RecordUntil(10);
  EXPECT_EQ(estimate.PriorAt(4), 1.0);
  EXPECT_LT(estimate.PriorAt(5), 0.1);
  EXPECT_EQ(estimate.FirstPoseWithEnoughLoops(), 5);
  // A loop that comes late counts from its arrival on, and the poses after
  // it are recorded again.
  AddLoops(&estimate, {1e-6}, 2);
  estimate.RecordUntil(12);
  EXPECT_LT(estimate.PriorAt(2), 1e-5);
  EXPECT_EQ(estimate.PriorAt(1), 1.0);
}

TEST(NoiseScaleEstimate, AcceptedLinksOutvoteThePriorAndAMinorityCannot) {
  NoiseScaleEstimate estimate(3);
  AddLoops(&estimate, ScaledChiSquare(100, 3, 0.5, 7));
  estimate.RecordUntil(1);
  const double prior = estimate.PriorAt(0);
  // Fewer accepted links than the prior weighs: the prior decides.
  estimate.SetClusterSample(0, 0.01 * 3 * (NoiseScaleEstimate::kPriorLinks - 1),
                            NoiseScaleEstimate::kPriorLinks - 1);
  EXPECT_DOUBLE_EQ(estimate.ValueAt(0), prior);
  // More: the map's errors decide.
  estimate.SetClusterSample(1, 0.01 * 3 * 2, 2);
  EXPECT_DOUBLE_EQ(estimate.ValueAt(0), 0.01);
  EXPECT_EQ(estimate.SourceAt(0), "clusters");
  // A wild cluster moves the median by as many votes as it has links: one
  // link leaves it, five bring it to the next value, the prior's.
  estimate.SetClusterSample(2, 1e4 * 3, 1);
  EXPECT_DOUBLE_EQ(estimate.ValueAt(0), 0.01);
  estimate.SetClusterSample(2, 1e4 * 3 * 5, 5);
  EXPECT_DOUBLE_EQ(estimate.ValueAt(0), prior);
  // Clusters that leave the map leave the estimate.
  estimate.RemoveClusterSample(0);
  estimate.RemoveClusterSample(1);
  EXPECT_DOUBLE_EQ(estimate.ValueAt(0), prior);
}

TEST(NoiseScaleEstimate, SamplesAtTheMinimumCarryTheMapsErrorOverTheLoops) {
  NoiseScaleEstimate estimate(3);
  std::vector<NoiseScaleEstimate::ClusterSample> at_minimum(10);
  for (int c = 0; c < 10; ++c) at_minimum[c] = {c, 0.1 * 6, 2};
  // The loops hold 6 of the map's 24: each sample counts four times.
  estimate.SetClusterSamplesAtMinimum(at_minimum, 24.0);
  EXPECT_DOUBLE_EQ(estimate.ValueAt(0), 0.4);
  // A map's error under the loops' own (not a minimum) never lowers them.
  estimate.SetClusterSamplesAtMinimum(at_minimum, 3.0);
  EXPECT_DOUBLE_EQ(estimate.ValueAt(0), 0.1);
}

TEST(NoiseScaleEstimate, SavedAndRestoredItDecidesTheSame) {
  NoiseScaleEstimate estimate(3);
  AddLoops(&estimate, ScaledChiSquare(50, 3, 0.3, 8), 3);
  estimate.RecordUntil(20);
  estimate.SetClusterSample(4, 0.2 * 3 * 12, 12);
  ByteWriter out;
  estimate.Save(&out);
  NoiseScaleEstimate restored(3);
  ByteReader in(out.bytes());
  restored.Restore(&in, 40, 12);
  for (const int pose : {0, 3, 19, 40}) {
    EXPECT_EQ(restored.ValueAt(pose), estimate.ValueAt(pose)) << pose;
    EXPECT_EQ(restored.PriorAt(pose), estimate.PriorAt(pose)) << pose;
  }
  EXPECT_EQ(restored.FirstPoseWithEnoughLoops(),
            estimate.FirstPoseWithEnoughLoops());
}

TEST(NoiseScaleEstimate, ARestoredRecordThatCannotBeIsRefusedNamingWhy) {
  const auto refusal = [](int arrival, std::int64_t recorded,
                          std::int64_t poses, int links) {
    ByteWriter out;
    out.Int(1);  // one loop sample
    out.Int(arrival);
    out.Double(0.4);
    out.Int(recorded);
    out.Int(poses);
    out.Int(1);  // one cluster sample
    out.Double(0.2);
    out.Int(links);
    NoiseScaleEstimate estimate(3);
    ByteReader in(out.bytes());
    try {
      estimate.Restore(&in, 10, 20);
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("restored");
  };
  EXPECT_EQ(refusal(0, 1, 5, 4), "restored");
  EXPECT_NE(refusal(0, 2, 5, 4).find("does not fit its 1 samples"),
            std::string::npos);
  EXPECT_NE(refusal(0, 1, 11, 4).find("a graph of 10 poses"),
            std::string::npos);
  EXPECT_NE(refusal(-4, 1, 5, 4).find("arrived with -4 poses"),
            std::string::npos);
  EXPECT_NE(refusal(0, 1, 5, -3).find("has -3 links"), std::string::npos);
  // More votes than the clusters have links is refused before any is cast
  // (a damaged count would otherwise fill the memory).
  EXPECT_EQ(refusal(0, 1, 5, 20), "restored");
  EXPECT_NE(refusal(0, 1, 5, 21).find("has 21 links (20 links may vote"),
            std::string::npos);
  EXPECT_NE(refusal(0, 1, 5, 2000000000).find("has 2000000000 links"),
            std::string::npos);
}

}  // namespace
}  // namespace rrr
