// libFuzzer target: the node's message conversion on arbitrary serialized
// messages. The bytes are read as a LoopClosure and as an Odometry message
// (as roscpp would deserialize them); every conversion either refuses with a
// reason or gives finite poses and a symmetric positive definite information
// matrix, in 2D and 3D.
#include <nav_msgs/Odometry.h>
#include <ros/serialization.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "../src/ros/msg_conversion.h"
#include "rrr/graph/odometry_noise.h"
#include "rrr_slam/LoopClosure.h"

namespace {

// A serialized message of type M from `data`, or false if it is too short.
template <class M>
bool Deserialize(const uint8_t* data, size_t size, M* out) {
  // Never a null buffer, as roscpp's never is (IStream computes an offset
  // from it before checking the length).
  std::vector<uint8_t> copy(size + 1);
  std::copy(data, data + size, copy.begin());
  ros::serialization::IStream stream(copy.data(), static_cast<uint32_t>(size));
  try {
    ros::serialization::deserialize(stream, *out);
  } catch (const ros::serialization::StreamOverrunException&) {
    return false;
  }
  return true;
}

template <class Pose>
void Convert(const geometry_msgs::PoseWithCovariance& in) {
  Pose pose;
  std::string why;
  if (rrr_ros::FromRos(in.pose, &pose, &why)) {
    if (!pose.Log().allFinite()) std::abort();
  } else if (why.empty()) {
    std::abort();  // a refusal must say why
  }
  typename rrr::Constraint<Pose>::Information information;
  why.clear();
  if (rrr_ros::InformationFromCovariance<Pose>(in.covariance, &information,
                                               &why)) {
    if (!information.allFinite() ||
        !information.isApprox(information.transpose()) ||
        information.llt().info() != Eigen::Success) {
      std::abort();
    }
  } else if (why.empty()) {
    std::abort();
  }
}

template <class Pose>
void ConvertOdometry(const nav_msgs::Odometry& msg) {
  Pose pose;
  std::string why;
  // rrr_node refuses a keyframe whose motion from the last is not finite.
  if (!rrr_ros::FromRos(msg.pose.pose, &pose, &why) ||
      !pose.Log().allFinite()) {
    return;
  }
  const rrr::OdometryCovariance covariance =
      rrr_ros::FromRos(msg.pose.covariance);
  const rrr::OdometryNoiseModel<Pose> model(
      rrr::Constraint<Pose>::Information::Identity(), 0.01);
  // The motion from the origin with no covariance there to this message.
  const auto information = model.EdgeInformation(
      Pose(), rrr::OdometryCovariance::Zero(), pose, covariance, true);
  if (!information.allFinite() || information.llt().info() != Eigen::Success) {
    std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  rrr_slam::LoopClosure loop;
  if (Deserialize(data, size, &loop)) {
    Convert<rrr::Pose2>(loop.relative_pose);
    Convert<rrr::Pose3>(loop.relative_pose);
  }
  nav_msgs::Odometry odometry;
  if (Deserialize(data, size, &odometry)) {
    Convert<rrr::Pose2>(odometry.pose);
    Convert<rrr::Pose3>(odometry.pose);
    ConvertOdometry<rrr::Pose2>(odometry);
    ConvertOdometry<rrr::Pose3>(odometry);
  }
  return 0;
}
