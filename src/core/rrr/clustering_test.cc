#include "rrr/rrr/clustering.h"

#include <gtest/gtest.h>

namespace rrr {
namespace {

TEST(Clustering, NearbyLoopsShareAClusterAndFarOnesDoNot) {
  Clustering c(10);
  EXPECT_EQ(c.Add(0, 100, 20), 0);
  EXPECT_EQ(c.Add(1, 105, 24), 0);  // both ends within 10
  EXPECT_EQ(c.Add(2, 105, 60), 1);  // end too far
  EXPECT_EQ(c.Add(3, 200, 22), 2);  // start too far
  ASSERT_EQ(c.clusters().size(), 3u);
  EXPECT_EQ(c.clusters()[0].loops, (std::vector<int>{0, 1}));
}

TEST(Clustering, LoopsOfAnotherGroupNeverShareACluster) {
  Clustering c(10);
  c.Add(0, 100, 20, 1);
  EXPECT_EQ(c.Add(1, 101, 21, 2), 1);  // as near, between other chains
  EXPECT_EQ(c.Add(2, 102, 22, 1), 0);
  EXPECT_EQ(c.clusters()[1].group, 2);
}

TEST(Clustering, BatchOrderTakesTheLaterEndAsTheStart) {
  std::vector<int> cluster_of;
  const std::vector<Cluster> clusters =
      ClusterInBatchOrder({{100, 20}, {22, 103}}, 10, &cluster_of);
  ASSERT_EQ(clusters.size(), 1u);
  EXPECT_EQ(clusters[0].start_high, 103);
  EXPECT_EQ(clusters[0].end_high, 22);
}

TEST(Clustering, WindowIsStrict) {
  Clustering c(10);
  c.Add(0, 100, 20);
  EXPECT_EQ(c.Add(1, 110, 20), 1);  // |110 - 100| = 10 is not < 10
  EXPECT_EQ(c.Add(2, 109, 29), 0);
}

TEST(Clustering, RangesWidenSoAClusterCanGrowAlongARevisit) {
  Clustering c(10);
  for (int k = 0; k < 10; ++k) EXPECT_EQ(c.Add(k, 100 + 8 * k, 8 * k), 0);
  const Cluster& cl = c.clusters()[0];
  EXPECT_EQ(cl.start_low, 100);
  EXPECT_EQ(cl.start_high, 172);
  EXPECT_EQ(cl.end_low, 0);
  EXPECT_EQ(cl.end_high, 72);
}

TEST(Clustering, JoinsTheFirstMatchingClusterInCreationOrder) {
  Clustering c(10);
  c.Add(0, 100, 20);  // cluster 0
  c.Add(1, 115, 20);  // cluster 1 (start 15 away from cluster 0)
  // 108 is near both clusters' starts; cluster 0 came first.
  EXPECT_EQ(c.Add(2, 108, 21), 0);
}

}  // namespace
}  // namespace rrr
