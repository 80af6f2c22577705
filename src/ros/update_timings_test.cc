#include "update_timings.h"

#include <gtest/gtest.h>

namespace rrr_ros {
namespace {

TEST(UpdateTimings, SummarizesNothingAsZeros) {
  const UpdateTimings::Summary s = UpdateTimings().Summarize();
  EXPECT_EQ(s.latency_max, 0.0);
  EXPECT_EQ(s.update_p99, 0.0);
  EXPECT_EQ(s.last_update, 0.0);
}

TEST(UpdateTimings, QuantilesAndTheRecentMaximum) {
  UpdateTimings timings;
  timings.AddUpdate(9.0);  // long ago: leaves the recent window
  for (size_t k = 1; k <= UpdateTimings::kRecentUpdates; ++k) {
    timings.AddUpdate(0.001 * k);
  }
  for (int k = 0; k <= 100; ++k) timings.AddLatency(0.01 * k);
  const UpdateTimings::Summary s = timings.Summarize();
  EXPECT_DOUBLE_EQ(s.update_max, 9.0);
  EXPECT_DOUBLE_EQ(s.recent_update_max, 0.1);
  EXPECT_DOUBLE_EQ(s.last_update, 0.1);
  EXPECT_DOUBLE_EQ(s.latency_p50, 0.5);
  EXPECT_DOUBLE_EQ(s.latency_p99, 0.99);
  EXPECT_DOUBLE_EQ(s.latency_max, 1.0);
}

}  // namespace
}  // namespace rrr_ros
