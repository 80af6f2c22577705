// The keyframes an odometry stream yields, and their corrected poses.
#ifndef RRR_GRAPH_KEYFRAME_TRACK_H_
#define RRR_GRAPH_KEYFRAME_TRACK_H_

#include <cstdint>
#include <string>
#include <vector>

#include "rrr/graph/keyframe_stamps.h"
#include "rrr/graph/odometry_noise.h"

namespace rrr {

// A keyframe, or a reading that may become one, as the robot's odometry
// reported it: its time stamp, its pose in the odometry frame and that
// pose's covariance.
template <class Pose>
struct KeyframeRecord {
  std::int64_t stamp_ns = 0;
  Pose odometry_pose;
  OdometryCovariance covariance = OdometryCovariance::Zero();
};

// The keyframes of one odometry stream, in order (their stamps, odometry
// poses and the newest one's covariance), and the map: their corrected
// poses in the map frame, which is the odometry frame of the first keyframe.
// A keyframe appended after the last SetMap() is placed in the map by its
// odometry motion from the one before.
template <class Pose>
class KeyframeTrack {
 public:
  // What Judge() makes of a reading.
  struct Reading {
    std::string problem;    // why the reading is refused; "" if it is not
    bool keyframe = false;  // the reading is the next keyframe
    Pose motion;            // from the newest keyframe (identity if none)
  };

  // Readings that moved at most `translation` m and `rotation` rad from the
  // newest keyframe make no keyframe (both 0: every reading does); stamps
  // match within `stamp_tolerance_ns` (KeyframeStamps). Throws
  // std::invalid_argument if any of them is negative.
  KeyframeTrack(double translation, double rotation,
                std::int64_t stamp_tolerance_ns);

  // Judges `reading` as the next keyframe: refused if it is stamped before
  // the newest keyframe or its motion from it is not finite; a keyframe if
  // it is the first or moved more than the thresholds.
  Reading Judge(const KeyframeRecord<Pose>& reading) const;
  // Appends `keyframe`. Throws std::invalid_argument if Judge() refuses it.
  void Append(const KeyframeRecord<Pose>& keyframe);

  bool empty() const { return odometry_.empty(); }
  int size() const { return static_cast<int>(odometry_.size()); }
  // The newest keyframe; the track must not be empty.
  KeyframeRecord<Pose> newest() const;
  const KeyframeStamps& stamps() const { return stamps_; }

  // Sets the map to `estimates` (one per keyframe, in any frame) moved
  // rigidly so that the first keyframe sits at its odometry pose. Throws
  // std::invalid_argument if there is not one per keyframe.
  void SetMap(const std::vector<Pose>& estimates);
  // Moves the newest keyframe's map pose where SetMap() would put it with
  // estimates whose first is `first` and whose last is `newest`: MapToOdom()
  // and the keyframes appended next follow; the other map poses stay until
  // the next SetMap(). Throws std::logic_error if the track is empty.
  void SetNewest(const Pose& first, const Pose& newest);
  // One corrected pose per keyframe, in the map frame.
  const std::vector<Pose>& map() const { return map_; }
  // The map → odometry frame transform: the correction that takes the
  // newest keyframe's odometry pose to its map pose (identity while empty).
  Pose MapToOdom() const;

 private:
  double translation_, rotation_;
  KeyframeStamps stamps_;
  std::vector<Pose> odometry_;
  OdometryCovariance newest_covariance_ = OdometryCovariance::Zero();
  std::vector<Pose> map_;
};

}  // namespace rrr

#endif  // RRR_GRAPH_KEYFRAME_TRACK_H_
