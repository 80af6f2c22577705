// FleetNode: its inputs, taken on the worker (the class is in
// fleet_node.cc, instantiated there; these members here).
#include <mutex>
#include <string>
#include <utility>

#include "fleet_node.h"
#include "msg_conversion.h"
#include "rrr_slam/Keyframe.h"
#include "status_messages.h"

namespace rrr_ros {

template <class Pose>
void FleetNode<Pose>::Process(const RobotOdometry& odometry) {
  const nav_msgs::Odometry& msg = *odometry.msg;
  const int r = odometry.robot;
  const std::string what = options_.robots[r] + " odometry";
  const std::string& frame = msg.header.frame_id;
  if (!frame.empty() && frame != RobotFrame(r, options_.odom_frame) &&
      frame != options_.odom_frame) {
    return status_.CountInvalid(what, msg.header.seq,
                                "frame '" + frame +
                                    "' is not the robot's odometry frame '" +
                                    RobotFrame(r, options_.odom_frame) + "'");
  }
  Pose pose;
  std::string why;
  if (!FromRos(msg.pose.pose, &pose, &why)) {
    return status_.CountInvalid(what, msg.header.seq, why);
  }
  const rrr::KeyframeRecord<Pose> reading{
      static_cast<std::int64_t>(msg.header.stamp.toNSec()), pose,
      FromRos(msg.pose.covariance)};
  const auto taken = session_.AddReading(r, reading);
  if (!taken.problem.empty()) {
    return status_.CountInvalid(what, msg.header.seq, taken.problem);
  }
  if (taken.new_session && session_.fleet().sessions(r).size() > 1) {
    ROS_INFO("rrr_node: robot %s restarted: session %zu from keyframe %lld",
             options_.robots[r].c_str(),
             session_.fleet().sessions(r).size() - 1,
             static_cast<long long>(taken.id));
  }
  if (!taken.keyframe) return;
  changed_ = true;
  rrr_slam::Keyframe keyframe;
  keyframe.header.stamp = msg.header.stamp;
  keyframe.header.frame_id = RobotFrame(r, options_.odom_frame);
  keyframe.id = taken.id;
  keyframe.pose = msg.pose.pose;
  keyframe_pubs_[r].publish(keyframe);
}

template <class Pose>
void FleetNode<Pose>::Process(const rrr_slam::FleetLoopClosure::ConstPtr& msg) {
  const uint32_t seq = msg->loop.header.seq;
  const int from = session_.fleet().RobotIndex(msg->from_robot);
  const int to = session_.fleet().RobotIndex(msg->to_robot);
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
void FleetNode<Pose>::Process(const rrr_slam::LoopClosure::ConstPtr& msg) {
  AddCandidate(msg->header.seq, 0, 0, *msg);
}

template <class Pose>
void FleetNode<Pose>::AddCandidate(uint32_t seq, int from, int to,
                                   const rrr_slam::LoopClosure& loop) {
  const std::string what = "loop closure";
  Pose z;
  Information information;
  std::string why;
  if (!FromRos(loop.relative_pose.pose, &z, &why) ||
      !InformationFromCovariance<Pose>(loop.relative_pose.covariance,
                                       &information, &why)) {
    return status_.CountInvalid(what, seq, why);
  }
  try {
    if (loop.reference == rrr_slam::LoopClosure::BY_ID) {
      session_.AddLoop(from, loop.from_id, to, loop.to_id, z, information);
    } else {
      const auto from_ns = static_cast<std::int64_t>(loop.from_stamp.toNSec());
      const auto to_ns = static_cast<std::int64_t>(loop.to_stamp.toNSec());
      session_.AddLoopByStamp(from, from_ns, to, to_ns, z, information);
    }
    changed_ = true;
  } catch (const rrr::DegenerateCandidate& e) {
    std::lock_guard<std::mutex> lock(status_.mutex);
    CountCandidateDefect(e.defect(), &status_.counts);
    ROS_WARN_THROTTLE(5.0, "rrr_node: skipped loop closure message %u: %s", seq,
                      e.what());
  }
}

#define RRR_INSTANTIATE_FLEET_NODE_INPUTS(Pose)                   \
  template void FleetNode<Pose>::Process(const RobotOdometry&);   \
  template void FleetNode<Pose>::Process(                         \
      const rrr_slam::FleetLoopClosure::ConstPtr&);               \
  template void FleetNode<Pose>::Process(                         \
      const rrr_slam::LoopClosure::ConstPtr&);                    \
  template void FleetNode<Pose>::AddCandidate(uint32_t, int, int, \
                                              const rrr_slam::LoopClosure&);
RRR_INSTANTIATE_FLEET_NODE_INPUTS(rrr::Pose2)
RRR_INSTANTIATE_FLEET_NODE_INPUTS(rrr::Pose3)
#undef RRR_INSTANTIATE_FLEET_NODE_INPUTS

}  // namespace rrr_ros
