// Keyframes from an odometry stream, and their map.
#include "rrr/graph/keyframe_track.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "rrr/geometry/pose2.h"

namespace rrr {
namespace {

KeyframeRecord<Pose2> Reading(std::int64_t stamp_ns, const Pose2& pose) {
  KeyframeRecord<Pose2> reading;
  reading.stamp_ns = stamp_ns;
  reading.odometry_pose = pose;
  return reading;
}

// Whether two poses are the same within 1e-9.
bool Same(const Pose2& a, const Pose2& b) {
  return a.between(b).Log().norm() < 1e-9;
}

TEST(KeyframeTrack, MakesAKeyframeOfTheFirstReadingAndOfMotionPastAThreshold) {
  KeyframeTrack<Pose2> track(1.0, 0.5, 0);
  EXPECT_TRUE(track.Judge(Reading(0, Pose2(3.0, 4.0, 1.0))).keyframe);
  track.Append(Reading(0, Pose2(3.0, 4.0, 1.0)));
  const Pose2 start(3.0, 4.0, 1.0);
  // Up to the thresholds, inclusive: no keyframe.
  EXPECT_FALSE(track.Judge(Reading(1, start * Pose2(1.0, 0.0, 0.5))).keyframe);
  const auto moved = track.Judge(Reading(1, start * Pose2(0.6, 0.9, 0.0)));
  EXPECT_TRUE(moved.keyframe);
  EXPECT_TRUE(moved.problem.empty());
  EXPECT_TRUE(Same(moved.motion, Pose2(0.6, 0.9, 0.0)));
  EXPECT_TRUE(track.Judge(Reading(1, start * Pose2(0.0, 0.0, -0.6))).keyframe);
  // With both thresholds 0 every reading is a keyframe.
  KeyframeTrack<Pose2> every(0.0, 0.0, 0);
  every.Append(Reading(0, start));
  EXPECT_TRUE(every.Judge(Reading(1, start)).keyframe);
}

TEST(KeyframeTrack, RefusesReadingsStampedBeforeTheNewestOrNotFinite) {
  KeyframeTrack<Pose2> track(0.0, 0.0, 0);
  track.Append(Reading(100, Pose2()));
  const auto old = track.Judge(Reading(99, Pose2(1.0, 0.0, 0.0)));
  EXPECT_FALSE(old.keyframe);
  EXPECT_EQ(old.problem, "its stamp is older than the last keyframe's");
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(track.Judge(Reading(101, Pose2(nan, 0.0, 0.0))).problem,
            "the motion from the last keyframe is not finite");
  EXPECT_THROW(track.Append(Reading(99, Pose2())), std::invalid_argument);
  EXPECT_EQ(track.size(), 1);
  EXPECT_THROW(KeyframeTrack<Pose2>(-1.0, 0.0, 0), std::invalid_argument);
  EXPECT_THROW(KeyframeTrack<Pose2>(0.0, 0.0, -1), std::invalid_argument);
}

TEST(KeyframeTrack, AnchorsTheMapAtTheFirstKeyframeAndCorrectsTheNewest) {
  KeyframeTrack<Pose2> track(0.0, 0.0, 0);
  const std::vector<Pose2> odometry = {
      Pose2(1.0, 1.0, 0.5), Pose2(2.0, 1.5, 0.7), Pose2(3.0, 2.5, 0.9)};
  for (size_t k = 0; k < odometry.size(); ++k) {
    track.Append(Reading(static_cast<std::int64_t>(k), odometry[k]));
  }
  // Before any map: the odometry itself, no correction.
  for (size_t k = 0; k < odometry.size(); ++k) {
    EXPECT_TRUE(Same(track.map()[k], odometry[k])) << k;
  }
  EXPECT_TRUE(Same(track.MapToOdom(), Pose2()));
  // A map in another frame, which moves the newest keyframe.
  const Pose2 frame(-5.0, 2.0, 2.0);
  const Pose2 fix(0.3, -0.2, 0.1);
  const std::vector<Pose2> estimates = {
      frame * odometry[0].inverse() * odometry[0],
      frame * odometry[0].inverse() * odometry[1],
      frame * odometry[0].inverse() * odometry[2] * fix};
  track.SetMap(estimates);
  EXPECT_TRUE(Same(track.map()[0], odometry[0]));
  EXPECT_TRUE(Same(track.map()[1], odometry[1]));
  EXPECT_TRUE(Same(track.map()[2], odometry[2] * fix));
  EXPECT_TRUE(Same(track.MapToOdom() * odometry[2], track.map()[2]));
  // A later keyframe follows its odometry motion from the corrected one.
  const Pose2 next(4.0, 3.0, 1.0);
  track.Append(Reading(3, next));
  EXPECT_TRUE(
      Same(track.map()[3], odometry[2] * fix * odometry[2].between(next)));
  EXPECT_THROW(track.SetMap(estimates), std::invalid_argument);
}

TEST(KeyframeTrack, SetNewestCorrectsTheNewestAsSetMapWould) {
  const std::vector<Pose2> odometry = {
      Pose2(1.0, 1.0, 0.5), Pose2(2.0, 1.5, 0.7), Pose2(3.0, 2.5, 0.9)};
  KeyframeTrack<Pose2> whole(0.0, 0.0, 0), ends(0.0, 0.0, 0);
  EXPECT_THROW(ends.SetNewest(Pose2(), Pose2()), std::logic_error);
  for (size_t k = 0; k < odometry.size(); ++k) {
    whole.Append(Reading(static_cast<std::int64_t>(k), odometry[k]));
    ends.Append(Reading(static_cast<std::int64_t>(k), odometry[k]));
  }
  const Pose2 frame(-5.0, 2.0, 2.0);
  const std::vector<Pose2> estimates = {
      frame, frame * Pose2(1.1, 0.4, 0.2),
      frame * Pose2(2.0, 1.0, 0.5) * Pose2(0.3, -0.2, 0.1)};
  whole.SetMap(estimates);
  ends.SetNewest(estimates.front(), estimates.back());
  EXPECT_TRUE(Same(ends.map().back(), whole.map().back()));
  EXPECT_TRUE(Same(ends.MapToOdom(), whole.MapToOdom()));
  EXPECT_TRUE(Same(ends.map()[1], odometry[1]));  // until the next SetMap
  const Pose2 next(4.0, 3.0, 1.0);
  whole.Append(Reading(3, next));
  ends.Append(Reading(3, next));
  EXPECT_TRUE(Same(ends.map().back(), whole.map().back()));
}

}  // namespace
}  // namespace rrr
