// rrr_node's worker taking in its inputs: odometry messages become
// keyframes, loop-closure messages candidates (by keyframe id, or held until
// keyframes near their stamps exist); what cannot be used is counted and
// warned about.
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
  const rrr::OdometryCovariance covariance = FromRos(msg->pose.covariance);
  if (resumed_ && msg->header.stamp <= resumed_until_) {
    std::lock_guard<std::mutex> lock(status_.mutex);
    ++status_.counts.inputs_already_recorded;
    return;
  }
  const rrr::KeyframeRecord<Pose> reading{
      static_cast<std::int64_t>(msg->header.stamp.toNSec()), pose, covariance};
  const auto judged = keyframes_.Judge(reading);
  if (!judged.problem.empty()) {
    return status_.CountInvalid(kOdometry, msg->header.seq, judged.problem);
  }
  if (!judged.keyframe) return;
  if (keyframes_.empty()) {
    verifier_->AddFirstPose(0, pose);
    if (store_) store_->RecordFirstKeyframe(0, reading);
  } else {
    using Source = typename rrr::OdometryNoiseModel<Pose>::Source;
    Source source;
    const rrr::KeyframeRecord<Pose> newest = keyframes_.newest();
    const Information information = odometry_noise_.EdgeInformation(
        newest.odometry_pose, newest.covariance, pose, covariance,
        options_.use_odometry_covariance, &source);
    {
      std::lock_guard<std::mutex> lock(status_.mutex);
      ++(source == Source::kCovarianceChange
             ? status_.counts.odometry_information_from_covariance
             : status_.counts.odometry_information_from_motion);
    }
    const rrr::PoseId id = verifier_->AddOdometry(judged.motion, information);
    if (store_) {
      store_->RecordKeyframe(id, reading, judged.motion, information);
    }
  }
  keyframes_.Append(reading);
  new_keyframes_ = true;
  rrr_slam::Keyframe keyframe;
  keyframe.header.stamp = msg->header.stamp;
  keyframe.header.frame_id = options_.odom_frame;
  keyframe.id = verifier_->graph().ids().back();
  keyframe.pose = msg->pose.pose;
  keyframe_pub_.publish(keyframe);
  ResolveStampedLoops();
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
    return AddLoopCandidate(seq, msg->from_id, msg->to_id, z, information);
  }
  if (stamped_waiting_.full()) {
    return Skip(seq, rrr::CandidateDefect::kWaitingFull,
                std::to_string(stamped_waiting_.size()) +
                    " candidates wait for keyframes by stamp already");
  }
  const std::int64_t from_ns = msg->from_stamp.toNSec();
  const std::int64_t to_ns = msg->to_stamp.toNSec();
  const std::int64_t key =
      store_ ? store_->RecordStampedWaiting(seq, from_ns, to_ns, z, information)
             : 0;
  stamped_waiting_.Hold(from_ns, to_ns, {seq, key, z, information});
  ResolveStampedLoops();
}

template <class Pose>
void VerifierNode<Pose>::ResolveStampedLoops() {
  stamped_waiting_.Resolve(
      keyframes_.stamps(),
      [this](int from, int to, const StampedLoop& loop) {
        if (store_) store_->RecordStampedResolved(loop.key);
        AddLoopCandidate(loop.seq, verifier_->graph().ids()[from],
                         verifier_->graph().ids()[to], loop.z,
                         loop.information);
      },
      [this](const char* end, const StampedLoop& loop) {
        if (store_) store_->RecordStampedResolved(loop.key);
        Skip(loop.seq, rrr::CandidateDefect::kUnknownPose,
             "no keyframe within " + std::to_string(options_.stamp_tolerance) +
                 " s of its " + end + " stamp");
      });
}

template <class Pose>
void VerifierNode<Pose>::AddLoopCandidate(uint32_t seq, rrr::PoseId from,
                                          rrr::PoseId to, const Pose& z,
                                          const Information& information) {
  if (from < 0 || to < 0) {
    return Skip(seq, rrr::CandidateDefect::kUnknownPose,
                "keyframe ids start at 0");
  }
  try {
    const int number = verifier_->AddLoop(from, to, z, information);
    if (store_) store_->RecordCandidate(number, from, to, z, information);
  } catch (const rrr::DegenerateCandidate& e) {
    Skip(seq, e.defect(), e.what());
  }
}

template <class Pose>
void VerifierNode<Pose>::Skip(uint32_t seq, rrr::CandidateDefect defect,
                              const std::string& why) {
  uint64_t count;
  {
    std::lock_guard<std::mutex> lock(status_.mutex);
    CountCandidateDefect(defect, &status_.counts);
    count = CandidateDefects(status_.counts);
  }
  ROS_WARN_THROTTLE(
      5.0,
      "rrr_node: skipped loop closure message %u (%s): %s (%lu skipped "
      "candidates so far)",
      seq, rrr::ToString(defect), why.c_str(),
      static_cast<unsigned long>(count));
}

// The class is instantiated in verifier_node.cc; these members here.
template void VerifierNode<rrr::Pose2>::Process(
    const nav_msgs::Odometry::ConstPtr&);
template void VerifierNode<rrr::Pose2>::Process(
    const rrr_slam::LoopClosure::ConstPtr&);
template void VerifierNode<rrr::Pose2>::ResolveStampedLoops();
template void VerifierNode<rrr::Pose2>::AddLoopCandidate(uint32_t, rrr::PoseId,
                                                         rrr::PoseId,
                                                         const rrr::Pose2&,
                                                         const Information&);
template void VerifierNode<rrr::Pose2>::Skip(uint32_t, rrr::CandidateDefect,
                                             const std::string&);
template void VerifierNode<rrr::Pose3>::Process(
    const nav_msgs::Odometry::ConstPtr&);
template void VerifierNode<rrr::Pose3>::Process(
    const rrr_slam::LoopClosure::ConstPtr&);
template void VerifierNode<rrr::Pose3>::ResolveStampedLoops();
template void VerifierNode<rrr::Pose3>::AddLoopCandidate(uint32_t, rrr::PoseId,
                                                         rrr::PoseId,
                                                         const rrr::Pose3&,
                                                         const Information&);
template void VerifierNode<rrr::Pose3>::Skip(uint32_t, rrr::CandidateDefect,
                                             const std::string&);

}  // namespace rrr_ros
