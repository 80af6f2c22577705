// rrr_node's worker taking in its inputs: odometry messages become the
// session's readings, loop-closure messages its candidates (by keyframe id or
// by stamp); what cannot be used is counted and warned about.
#include <mutex>
#include <string>

#include "msg_conversion.h"
#include "rrr_slam/Keyframe.h"
#include "status_messages.h"
#include "verifier_node.h"

namespace rrr_ros {
namespace {

// Why a message in `frame` is not in the expected frame `name` (the `role`
// frame), or "" if it is; an empty frame is taken as the expected one.
std::string WrongFrame(const std::string& frame, const std::string& name,
                       const std::string& role) {
  if (frame.empty() || frame == name) return "";
  return "frame '" + frame + "' is not the " + role + " frame '" + name + "'";
}

}  // namespace

template <class Pose>
void VerifierNode<Pose>::Process(const nav_msgs::Odometry::ConstPtr& msg) {
  std::string why =
      WrongFrame(msg->header.frame_id, options_.odom_frame, "odometry");
  if (!why.empty())
    return status_.CountInvalid(kOdometry, msg->header.seq, why);
  Pose pose;
  if (!FromRos(msg->pose.pose, &pose, &why))
    return status_.CountInvalid(kOdometry, msg->header.seq, why);
  const auto taken = session_.AddReading(
      {static_cast<std::int64_t>(msg->header.stamp.toNSec()), pose,
       FromRos(msg->pose.covariance)});
  if (taken.already_recorded) {
    std::lock_guard<std::mutex> lock(status_.mutex);
    ++status_.counts.inputs_already_recorded;
    return;
  }
  if (!taken.problem.empty()) {
    return status_.CountInvalid(kOdometry, msg->header.seq, taken.problem);
  }
  if (!taken.keyframe) return;
  if (taken.id > 0) {
    std::lock_guard<std::mutex> lock(status_.mutex);
    ++(taken.information_from_covariance
           ? status_.counts.odometry_information_from_covariance
           : status_.counts.odometry_information_from_motion);
    status_.counts.odometry_restarts_joined += taken.restarted ? 1 : 0;
  }
  if (taken.restarted) {
    ROS_WARN(
        "rrr_node: odometry message %u is back at the origin of '%s' %.1f m "
        "from keyframe %lld: the odometry restarted, and keyframe %lld is "
        "joined to it by that jump, an odometry edge that did not happen. A "
        "robot whose odometry may restart belongs in a fleet of one "
        "(robots:=[<name>]), where a restart starts a new session",
        msg->header.seq, options_.odom_frame.c_str(), taken.jump,
        static_cast<long long>(taken.id - 1), static_cast<long long>(taken.id));
  }
  new_keyframes_ = true;
  rrr_slam::Keyframe keyframe;
  keyframe.header.stamp = msg->header.stamp;
  keyframe.header.frame_id = options_.odom_frame;
  keyframe.id = taken.id;
  keyframe.pose = msg->pose.pose;
  keyframe_pub_.publish(keyframe);
}

template <class Pose>
void VerifierNode<Pose>::Process(const rrr_slam::LoopClosure::ConstPtr& msg) {
  const uint32_t seq = msg->header.seq;
  std::string why =
      WrongFrame(msg->header.frame_id, options_.base_frame, "robot");
  if (!why.empty()) return status_.CountInvalid(kLoopClosure, seq, why);
  if (msg->reference != rrr_slam::LoopClosure::BY_ID &&
      msg->reference != rrr_slam::LoopClosure::BY_STAMP) {
    return status_.CountInvalid(kLoopClosure, seq,
                                "reference " + std::to_string(msg->reference) +
                                    " is neither BY_ID nor BY_STAMP");
  }
  Pose z;
  Information information;
  if (!FromRos(msg->relative_pose.pose, &z, &why) ||
      !InformationFromCovariance<Pose>(msg->relative_pose.covariance,
                                       &information, &why)) {
    return status_.CountInvalid(kLoopClosure, seq, why);
  }
  if (msg->reference == rrr_slam::LoopClosure::BY_ID) {
    session_.AddCandidate(seq, msg->from_id, msg->to_id, z, information);
  } else {
    session_.AddCandidateByStamp(seq, msg->from_stamp.toNSec(),
                                 msg->to_stamp.toNSec(), z, information);
  }
}

template <class Pose>
void VerifierNode<Pose>::Skip(const rrr::SkippedMessage& skipped) {
  uint64_t count;
  {
    std::lock_guard<std::mutex> lock(status_.mutex);
    CountCandidateDefect(skipped.defect, &status_.counts);
    count = CandidateDefects(status_.counts);
  }
  ROS_WARN_THROTTLE(
      5.0,
      "rrr_node: skipped loop closure message %lld (%s): %s (%lu skipped "
      "candidates so far)",
      static_cast<long long>(skipped.message), rrr::ToString(skipped.defect),
      skipped.why.c_str(), static_cast<unsigned long>(count));
}

// The class is instantiated in verifier_node.cc; these members here.
template void VerifierNode<rrr::Pose2>::Process(
    const nav_msgs::Odometry::ConstPtr&);
template void VerifierNode<rrr::Pose2>::Process(
    const rrr_slam::LoopClosure::ConstPtr&);
template void VerifierNode<rrr::Pose2>::Skip(const rrr::SkippedMessage&);
template void VerifierNode<rrr::Pose3>::Process(
    const nav_msgs::Odometry::ConstPtr&);
template void VerifierNode<rrr::Pose3>::Process(
    const rrr_slam::LoopClosure::ConstPtr&);
template void VerifierNode<rrr::Pose3>::Skip(const rrr::SkippedMessage&);

}  // namespace rrr_ros
