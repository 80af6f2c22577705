#include "simulated_robot.h"

#include <nav_msgs/Odometry.h>
#include <std_msgs/Bool.h>

#include <stdexcept>

#include "msg_conversion.h"
#include "rrr_slam/LoopClosure.h"

namespace rrr_ros {

SimulatedRobotOptions SimulatedRobotOptions::Read(const ros::NodeHandle& nh) {
  SimulatedRobotOptions o;
  int seed = static_cast<int>(o.world.seed);
  nh.param("poses", o.world.poses, o.world.poses);
  nh.param("false_loops", o.world.false_loops, o.world.false_loops);
  nh.param("group", o.world.group, o.world.group);
  nh.param("seed", seed, seed);
  o.world.seed = static_cast<std::uint64_t>(seed);
  nh.param("rate", o.rate, o.rate);
  nh.param("odom_frame", o.odom_frame, o.odom_frame);
  nh.param("base_frame", o.base_frame, o.base_frame);
  const std::string problem = o.world.Validate();
  if (!problem.empty()) {
    throw std::invalid_argument(nh.getNamespace() + ": " + problem);
  }
  if (!(o.rate > 0)) {
    throw std::invalid_argument(nh.resolveName("rate") + ": must be > 0");
  }
  return o;
}

SimulatedRobot::SimulatedRobot(ros::NodeHandle& nh, ros::NodeHandle& private_nh,
                               const SimulatedRobotOptions& options)
    : options_(options),
      world_(rrr::SimulateWorld(options.world)),
      chain_(rrr::ChainOf(world_.graph)) {
  const auto& g = world_.graph;
  odometry_ = g.ComposeOdometry();
  loops_at_.resize(g.num_poses());
  for (size_t k = 0; k < g.loops().size(); ++k) {
    const auto& l = g.loops()[k];
    loops_at_[std::max(l.from, l.to)].push_back(static_cast<int>(k));
  }
  odom_pub_ = nh.advertise<nav_msgs::Odometry>("odom", 100);
  loop_pub_ = nh.advertise<rrr_slam::LoopClosure>("loop_closures", 100);
  done_pub_ = private_nh.advertise<std_msgs::Bool>("done", 1, true);
  std_msgs::Bool done;
  done.data = false;
  done_pub_.publish(done);
  timer_ = nh.createTimer(ros::Duration(1.0 / options_.rate),
                          &SimulatedRobot::OnTimer, this);
}

void SimulatedRobot::OnTimer(const ros::TimerEvent&) {
  const auto& g = world_.graph;
  if (next_ >= g.num_poses()) return;
  // Wait for the verifier: a robot's first messages would be lost too.
  if (next_ == 0 && (odom_pub_.getNumSubscribers() == 0 ||
                     loop_pub_.getNumSubscribers() == 0)) {
    return;
  }
  const int k = next_++;
  const ros::Time now = ros::Time::now();
  stamps_.push_back(now);
  if (k > 0) {
    const auto step = chain_.Between(k - 1, k);
    covariance_ = rrr::OdometryNoiseModel<rrr::Pose2>::Grow(
        covariance_, odometry_[k], step.information);
  }
  nav_msgs::Odometry odom;
  odom.header.stamp = now;
  odom.header.frame_id = options_.odom_frame;
  odom.child_frame_id = options_.base_frame;
  odom.pose.pose = ToRos(odometry_[k]);
  odom.pose.covariance = ToRos(covariance_);
  odom_pub_.publish(odom);
  for (const int l : loops_at_[k]) {
    const auto& e = g.loops()[l];
    rrr_slam::LoopClosure loop;
    loop.header.stamp = now;
    loop.header.frame_id = options_.base_frame;
    loop.reference = rrr_slam::LoopClosure::BY_STAMP;
    loop.from_stamp = stamps_[e.from];
    loop.to_stamp = stamps_[e.to];
    loop.relative_pose.pose = ToRos(e.measurement);
    loop.relative_pose.covariance =
        CovarianceFromInformation<rrr::Pose2>(e.information);
    loop.confidence = -1.0;
    loop_pub_.publish(loop);
  }
  if (next_ == g.num_poses()) {
    std_msgs::Bool done;
    done.data = true;
    done_pub_.publish(done);
  }
}

}  // namespace rrr_ros
