// Converting the node's messages: what is refused, and why.
#include "msg_conversion.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"

namespace rrr_ros {
namespace {

using ::testing::HasSubstr;

geometry_msgs::Pose PoseAt(double x, double y, double z) {
  geometry_msgs::Pose pose;
  pose.position.x = x;
  pose.position.y = y;
  pose.position.z = z;
  pose.orientation.w = 1.0;
  return pose;
}

TEST(MsgConversion, RefusesAPositionBeyondAnyRobotsReach) {
  // Found by fuzzing: a finite z of -1.5e308 with a half-turn made the 3D
  // pose's logarithm overflow.
  geometry_msgs::Pose far = PoseAt(0.0, 0.0, -1.5182419756943659e308);
  far.orientation.w = 0.0;
  far.orientation.x = 0.948984619355599;
  far.orientation.y = 0.3153223623952684;
  rrr::Pose3 pose3;
  std::string why;
  EXPECT_FALSE(FromRos(far, &pose3, &why));
  EXPECT_THAT(why, HasSubstr("beyond 1000000000"));
  rrr::Pose2 pose2;
  why.clear();
  EXPECT_FALSE(FromRos(PoseAt(2e9, 0.0, 0.0), &pose2, &why));
  EXPECT_THAT(why, HasSubstr("the position has a coordinate of"));
  // A far but plausible position converts, with a finite logarithm.
  ASSERT_TRUE(FromRos(PoseAt(-1e8, 5e8, 1e9), &pose3, &why)) << why;
  EXPECT_TRUE(pose3.Log().allFinite());
  ASSERT_TRUE(FromRos(PoseAt(1e9, -1e9, 0.0), &pose2, &why)) << why;
  EXPECT_TRUE(pose2.Log().allFinite());
}

TEST(MsgConversion, RefusesValuesThatAreNotFiniteAndNonUnitQuaternions) {
  rrr::Pose3 pose;
  std::string why;
  EXPECT_FALSE(FromRos(PoseAt(0.0, NAN, 0.0), &pose, &why));
  EXPECT_EQ(why, "the pose has a value that is not finite");
  geometry_msgs::Pose scaled = PoseAt(0.0, 0.0, 0.0);
  scaled.orientation.w = 2.0;
  EXPECT_FALSE(FromRos(scaled, &pose, &why));
  EXPECT_THAT(why, HasSubstr("not a unit quaternion"));
}

}  // namespace
}  // namespace rrr_ros
