#include "rrr/rrr/map/cluster_strain.h"

#include <gtest/gtest.h>

namespace rrr {
namespace {

TEST(ClustersStrainedAbove, SumsEachClustersRiseOverItsGateMostStrainedFirst) {
  // Loops 0-1 in cluster 5, loop 2 in cluster 7, loops 3-4 in cluster 2.
  const std::vector<int> cluster_of_loop = {5, 5, 7, 2, 2};
  const std::vector<MapTrial::LoopStrain> map_loops = {{0, 1.0, 4.0},
                                                       {2, 2.0, 2.5},
                                                       {1, 1.0, 3.0},
                                                       {3, 5.0, 1.0},
                                                       {4, 0.0, 9.0}};
  const auto gate = [](int cluster) { return cluster == 5 ? 10.0 : 1.0; };
  // Rises: cluster 5 (3 + 2) / 10 = 0.5, cluster 7 0.5 / 1, cluster 2
  // (-4 + 9) / 1 = 5.
  const auto strained =
      ClustersStrainedAbove(map_loops, cluster_of_loop, gate, 0.0);
  ASSERT_EQ(strained.size(), 3u);
  EXPECT_EQ(strained[0], std::make_pair(5.0, 2));
  EXPECT_EQ(strained[1], std::make_pair(0.5, 7));  // ties: higher index first
  EXPECT_EQ(strained[2], std::make_pair(0.5, 5));
  // Only those above the threshold.
  const auto above_one =
      ClustersStrainedAbove(map_loops, cluster_of_loop, gate, 1.0);
  ASSERT_EQ(above_one.size(), 1u);
  EXPECT_EQ(above_one[0].second, 2);
}

TEST(ClustersStrainedAbove, AnEasedClusterIsNotStrained) {
  const std::vector<MapTrial::LoopStrain> map_loops = {{0, 4.0, 1.0}};
  EXPECT_TRUE(ClustersStrainedAbove(
                  map_loops, {0}, [](int) { return 1.0; }, 0.0)
                  .empty());
}

}  // namespace
}  // namespace rrr
