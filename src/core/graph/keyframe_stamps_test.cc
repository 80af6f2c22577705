// Naming keyframes by time stamp.
#include "rrr/graph/keyframe_stamps.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace rrr {
namespace {

TEST(KeyframeStamps, FindsTheNearestKeyframeWithinTheTolerance) {
  KeyframeStamps stamps(100);
  EXPECT_EQ(stamps.Find(0), KeyframeStamps::kNotYet);
  for (const std::int64_t t : {1000, 2000, 2000, 3000}) stamps.Append(t);
  EXPECT_EQ(stamps.Find(1000), 0);
  EXPECT_EQ(stamps.Find(1099), 0);
  EXPECT_EQ(stamps.Find(1100), 0);  // the tolerance is inclusive
  EXPECT_EQ(stamps.Find(1101), KeyframeStamps::kNone);
  EXPECT_EQ(stamps.Find(899), KeyframeStamps::kNone);  // before the first
  EXPECT_EQ(stamps.Find(1950), 1);  // the first of two equal stamps
  EXPECT_EQ(stamps.Find(2040), 2);  // just after them: the later
  EXPECT_EQ(stamps.Find(2960), 3);
  EXPECT_EQ(stamps.Find(3000), 3);
  EXPECT_EQ(stamps.Find(3001), KeyframeStamps::kNotYet);
  EXPECT_EQ(stamps.newest(), 3000);
}

TEST(KeyframeStamps, TakesTheLaterOfTwoEquallyNearKeyframes) {
  KeyframeStamps stamps(500);
  stamps.Append(1000);
  stamps.Append(2000);
  EXPECT_EQ(stamps.Find(1500), 1);
  EXPECT_EQ(stamps.Find(1499), 0);
}

TEST(KeyframeStamps, RejectsStampsGoingBackAndANegativeTolerance) {
  KeyframeStamps stamps(0);
  stamps.Append(5);
  EXPECT_THROW(stamps.Append(4), std::invalid_argument);
  EXPECT_EQ(stamps.stamps().size(), 1u);
  EXPECT_EQ(stamps.Find(5), 0);
  EXPECT_EQ(stamps.Find(4), KeyframeStamps::kNone);
  EXPECT_THROW(KeyframeStamps(-1), std::invalid_argument);
}

}  // namespace
}  // namespace rrr
