#include "rrr/graph/odometry_input.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"

namespace rrr {
namespace {

// The message of the std::invalid_argument Validate<Pose> throws for
// `options`, or "" if they validate.
template <class Pose>
std::string Refusal(const OdometryInputOptions& options) {
  try {
    Validate<Pose>(options);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(OdometryInput, EachOptionOutOfRangeIsRefusedByName) {
  EXPECT_EQ(Refusal<Pose2>(OdometryInputOptions()), "");
  OdometryInputOptions o;
  o.odometry_information = {10.0, 10.0, 50.0};
  EXPECT_EQ(Refusal<Pose2>(o), "");
  // Three values suit a 2D pose, not a 3D one.
  EXPECT_NE(Refusal<Pose3>(o).find("odometry_information needs 6 values"),
            std::string::npos);
  o.odometry_information = {10.0, 0.0, 50.0};
  EXPECT_NE(Refusal<Pose2>(o).find("odometry_information"), std::string::npos);

  o = OdometryInputOptions();
  o.odometry_min_motion = 0.0;
  EXPECT_NE(Refusal<Pose2>(o).find("odometry_min_motion"), std::string::npos);
  o = OdometryInputOptions();
  o.keyframe_rotation = -0.1;
  EXPECT_NE(Refusal<Pose3>(o).find("keyframe thresholds"), std::string::npos);
  o = OdometryInputOptions();
  o.stamp_tolerance_ns = -1;
  EXPECT_NE(Refusal<Pose2>(o).find("stamp tolerance"), std::string::npos);
}

TEST(OdometryInput, TheNoiseModelAndTheTrackAreMadeOnlyOfValidOptions) {
  OdometryInputOptions o;
  o.use_odometry_covariance = false;
  o.odometry_information = {4.0, 4.0, 9.0};
  o.odometry_min_motion = 0.5;
  // 4 per metre over at least 0.5 m: at most 8 along x for a short motion.
  const Constraint<Pose2>::Information short_motion =
      NoiseModelOf<Pose2>(o).FromMotion(Pose2(0.1, 0.0, 0.0));
  EXPECT_DOUBLE_EQ(short_motion(0, 0), 8.0);
  EXPECT_DOUBLE_EQ(short_motion(2, 2), 18.0);
  o.keyframe_translation = -1.0;
  EXPECT_THROW(NoiseModelOf<Pose2>(o), std::invalid_argument);
  EXPECT_THROW(TrackOf<Pose2>(o), std::invalid_argument);
}

}  // namespace
}  // namespace rrr
