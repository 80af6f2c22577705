// rrr_node's worker taking in its inputs: odometry messages become the
// session's readings, loop-closure messages its candidates (by keyframe id or
// by stamp); what cannot be used is counted and warned about.
#include <mutex>
#include <string>
#include <utility>

#include "msg_conversion.h"
#include "rrr_slam/Keyframe.h"
#include "status_messages.h"
#include "verifier_node.h"

namespace rrr_ros {

template <class Pose>
void VerifierNode<Pose>::Process(const RobotOdometry& odometry) {
  const nav_msgs::Odometry& msg = *odometry.msg;
  const int r = odometry.robot;
  const std::string what = RobotFrame(r, "odometry");
  const std::string& frame = msg.header.frame_id;
  if (!frame.empty() && frame != RobotFrame(r, options_.odom_frame) &&
      frame != options_.odom_frame) {
    return status_.CountInvalid(what, msg.header.seq,
                                "frame '" + frame +
                                    "' is not the odometry frame '" +
                                    RobotFrame(r, options_.odom_frame) + "'");
  }
  Pose pose;
  std::string why;
  if (!FromRos(msg.pose.pose, &pose, &why)) {
    return status_.CountInvalid(what, msg.header.seq, why);
  }
  const auto taken = session_.AddReading(
      r, {static_cast<std::int64_t>(msg.header.stamp.toNSec()), pose,
          FromRos(msg.pose.covariance)});
  if (taken.already_recorded) {
    std::lock_guard<std::mutex> lock(status_.mutex);
    ++status_.counts.inputs_already_recorded;
    return;
  }
  if (!taken.problem.empty()) {
    return status_.CountInvalid(what, msg.header.seq, taken.problem);
  }
  if (!taken.keyframe) return;
  if (!taken.new_session) {
    std::lock_guard<std::mutex> lock(status_.mutex);
    ++(taken.information_from_covariance
           ? status_.counts.odometry_information_from_covariance
           : status_.counts.odometry_information_from_motion);
    status_.counts.odometry_restarts_joined += taken.restarted ? 1 : 0;
  }
  if (taken.new_session && session_.sessions(r).size() > 1) {
    ROS_INFO(
        "rrr_node: %s message %u restarted the odometry: session %zu from "
        "keyframe %lld, joined to the others by loop closures alone",
        what.c_str(), msg.header.seq, session_.sessions(r).size() - 1,
        static_cast<long long>(taken.id));
  }
  if (taken.restarted) {
    ROS_WARN(
        "rrr_node: %s message %u restarted the odometry %.1f m from keyframe "
        "%lld; the published procedure judges one chain, so keyframe %lld is "
        "joined to it by that jump, an odometry edge that did not happen",
        what.c_str(), msg.header.seq, taken.jump,
        static_cast<long long>(taken.id - 1), static_cast<long long>(taken.id));
  }
  new_keyframes_ = true;
  rrr_slam::Keyframe keyframe;
  keyframe.header.stamp = msg.header.stamp;
  keyframe.header.frame_id = RobotFrame(r, options_.odom_frame);
  keyframe.id = taken.id;
  keyframe.pose = msg.pose.pose;
  keyframe_pubs_[r].publish(keyframe);
}

template <class Pose>
void VerifierNode<Pose>::Process(
    const rrr_slam::FleetLoopClosure::ConstPtr& msg) {
  const uint32_t seq = msg->loop.header.seq;
  const int from = session_.RobotIndex(msg->from_robot);
  const int to = session_.RobotIndex(msg->to_robot);
  for (const auto& [index, name] :
       {std::pair(from, &msg->from_robot), {to, &msg->to_robot}}) {
    if (index < 0) {
      return status_.CountInvalid(
          "fleet loop closure", seq,
          "robot '" + *name + "' is not among the robots");
    }
  }
  AddCandidate(seq, from, to, msg->loop);
}

template <class Pose>
void VerifierNode<Pose>::Process(const rrr_slam::LoopClosure::ConstPtr& msg) {
  AddCandidate(msg->header.seq, 0, 0, *msg);
}

template <class Pose>
void VerifierNode<Pose>::AddCandidate(uint32_t seq, int from, int to,
                                      const rrr_slam::LoopClosure& loop) {
  const char* what = "loop closure";
  const std::string& frame = loop.header.frame_id;
  if (!frame.empty() && frame != options_.base_frame &&
      frame != RobotFrame(from, options_.base_frame) &&
      frame != RobotFrame(to, options_.base_frame)) {
    return status_.CountInvalid(
        what, seq,
        "frame '" + frame + "' is not the robot frame '" +
            RobotFrame(from, options_.base_frame) + "'");
  }
  if (loop.reference != rrr_slam::LoopClosure::BY_ID &&
      loop.reference != rrr_slam::LoopClosure::BY_STAMP) {
    return status_.CountInvalid(what, seq,
                                "reference " + std::to_string(loop.reference) +
                                    " is neither BY_ID nor BY_STAMP");
  }
  Pose z;
  Information information;
  std::string why;
  if (!FromRos(loop.relative_pose.pose, &z, &why) ||
      !InformationFromCovariance<Pose>(loop.relative_pose.covariance,
                                       &information, &why)) {
    return status_.CountInvalid(what, seq, why);
  }
  if (loop.reference == rrr_slam::LoopClosure::BY_ID) {
    session_.AddCandidate(seq, from, loop.from_id, to, loop.to_id, z,
                          information);
  } else {
    session_.AddCandidateByStamp(
        seq, from, static_cast<std::int64_t>(loop.from_stamp.toNSec()), to,
        static_cast<std::int64_t>(loop.to_stamp.toNSec()), z, information);
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
#define RRR_INSTANTIATE_NODE_INPUTS(Pose)                          \
  template void VerifierNode<Pose>::Process(const RobotOdometry&); \
  template void VerifierNode<Pose>::Process(                       \
      const rrr_slam::FleetLoopClosure::ConstPtr&);                \
  template void VerifierNode<Pose>::Process(                       \
      const rrr_slam::LoopClosure::ConstPtr&);                     \
  template void VerifierNode<Pose>::AddCandidate(                  \
      uint32_t, int, int, const rrr_slam::LoopClosure&);           \
  template void VerifierNode<Pose>::Skip(const rrr::SkippedMessage&);
RRR_INSTANTIATE_NODE_INPUTS(rrr::Pose2)
RRR_INSTANTIATE_NODE_INPUTS(rrr::Pose3)
#undef RRR_INSTANTIATE_NODE_INPUTS

}  // namespace rrr_ros
