// ROS messages <-> core types, and nothing else.
#ifndef RRR_ROS_MSG_CONVERSION_H_
#define RRR_ROS_MSG_CONVERSION_H_

#include <geometry_msgs/Pose.h>
#include <geometry_msgs/Transform.h>

#include <boost/array.hpp>
#include <string>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/graph/odometry_noise.h"
#include "rrr/graph/pose_graph.h"

namespace rrr_ros {

// A ROS pose as a core pose; 2D keeps x, y and yaw. Returns false (with a
// reason) if a value is not finite, a position coordinate is over 10⁹ m or
// the quaternion is not near unit norm.
bool FromRos(const geometry_msgs::Pose& in, rrr::Pose2* out, std::string* why);
bool FromRos(const geometry_msgs::Pose& in, rrr::Pose3* out, std::string* why);

geometry_msgs::Pose ToRos(const rrr::Pose2& pose);
geometry_msgs::Pose ToRos(const rrr::Pose3& pose);
geometry_msgs::Transform ToRosTransform(const rrr::Pose2& pose);
geometry_msgs::Transform ToRosTransform(const rrr::Pose3& pose);

// The information matrix of a PoseWithCovariance covariance (x y z roll
// pitch yaw; 2D keeps x, y and yaw). Returns false (with a reason) if the
// covariance is not finite or not symmetric, or if
// rrr::InformationFromCovariance refuses it (not positive definite, numerically
// singular).
template <class Pose>
bool InformationFromCovariance(const boost::array<double, 36>& covariance,
                               typename rrr::Constraint<Pose>::Information* out,
                               std::string* why);
// The covariance of an information matrix, laid out as
// InformationFromCovariance reads it (other entries 0).
template <class Pose>
boost::array<double, 36> CovarianceFromInformation(
    const typename rrr::Constraint<Pose>::Information& information);

// A message's 6 × 6 pose covariance, row-major as geometry_msgs carries it.
rrr::OdometryCovariance FromRos(const boost::array<double, 36>& covariance);
boost::array<double, 36> ToRos(const rrr::OdometryCovariance& covariance);

}  // namespace rrr_ros

#endif  // RRR_ROS_MSG_CONVERSION_H_
