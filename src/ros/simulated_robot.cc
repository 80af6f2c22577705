#include "simulated_robot.h"

#include <nav_msgs/Odometry.h>
#include <std_msgs/Bool.h>

#include <algorithm>
#include <stdexcept>
#include <utility>

#include "msg_conversion.h"
#include "rrr_slam/FleetLoopClosure.h"
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
  nh.param("robots", o.robots, o.robots);
  nh.param("robot", o.robot, o.robot);
  nh.param("restart_at", o.restart_at, o.restart_at);
  if (!o.robots.empty() &&
      std::find(o.robots.begin(), o.robots.end(), o.robot) == o.robots.end()) {
    throw std::invalid_argument(nh.resolveName("robot") + ": '" + o.robot +
                                "' is not among the robots");
  }
  if (static_cast<int>(o.robots.size()) * 2 > o.world.poses) {
    throw std::invalid_argument(nh.resolveName("robots") +
                                ": more robots than half the poses");
  }
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
  const int robots = std::max<int>(1, options_.robots.size());
  for (int r = 0; r < robots; ++r) {
    first_of_robot_.push_back(g.num_poses() * r / robots);
  }
  const int me =
      static_cast<int>(std::find(options_.robots.begin(), options_.robots.end(),
                                 options_.robot) -
                       options_.robots.begin());
  first_ = options_.robots.empty() ? 0 : first_of_robot_[me];
  last_ = options_.robots.empty() || me + 1 == robots
              ? g.num_poses() - 1
              : first_of_robot_[me + 1] - 1;
  odometry_.assign(g.num_poses(), rrr::Pose2());
  for (int p = first_ + 1; p <= last_; ++p) {
    odometry_[p] =
        p == first_ + options_.restart_at
            ? rrr::Pose2()
            : odometry_[p - 1] * chain_.Between(p - 1, p).measurement;
  }
  loops_at_.resize(g.num_poses());
  for (size_t k = 0; k < g.loops().size(); ++k) {
    const auto& l = g.loops()[k];
    if (options_.robots.empty()) {
      loops_at_[std::max(l.from, l.to)].push_back(static_cast<int>(k));
      continue;
    }
    // Its later end, counted in each robot's part; a tie: the later robot's.
    const auto later = std::max(
        {std::pair(l.from - first_of_robot_[RobotOf(l.from)], RobotOf(l.from)),
         std::pair(l.to - first_of_robot_[RobotOf(l.to)], RobotOf(l.to))});
    if (later.second == me) {
      loops_at_[first_ + later.first].push_back(static_cast<int>(k));
    }
  }
  odom_pub_ = nh.advertise<nav_msgs::Odometry>("odom", 100);
  loop_pub_ = options_.robots.empty()
                  ? nh.advertise<rrr_slam::LoopClosure>("loop_closures", 100)
                  : nh.advertise<rrr_slam::FleetLoopClosure>(
                        "fleet_loop_closures", 100);
  done_pub_ = private_nh.advertise<std_msgs::Bool>("done", 1, true);
  std_msgs::Bool done;
  done.data = false;
  done_pub_.publish(done);
  timer_ = nh.createTimer(ros::Duration(1.0 / options_.rate),
                          &SimulatedRobot::OnTimer, this);
}

int SimulatedRobot::RobotOf(int p) const {
  return static_cast<int>(std::upper_bound(first_of_robot_.begin(),
                                           first_of_robot_.end(), p) -
                          first_of_robot_.begin()) -
         1;
}

void SimulatedRobot::OnTimer(const ros::TimerEvent&) {
  const auto& g = world_.graph;
  if (next_ == 0) next_ = first_;
  if (next_ > last_) return;
  // Wait for the verifier: a robot's first messages would be lost too.
  if (next_ == first_ && (odom_pub_.getNumSubscribers() == 0 ||
                          loop_pub_.getNumSubscribers() == 0)) {
    return;
  }
  const int k = next_++;
  const ros::Time now = ros::Time::now();
  stamps_.resize(g.num_poses());
  stamps_[k] = now;
  if (k == first_ + options_.restart_at) {
    covariance_ = rrr::OdometryCovariance::Zero();  // restarted
  } else if (k > first_) {
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
    loop.relative_pose.pose = ToRos(e.measurement);
    loop.relative_pose.covariance =
        CovarianceFromInformation<rrr::Pose2>(e.information);
    loop.confidence = -1.0;
    if (options_.robots.empty()) {
      loop.reference = rrr_slam::LoopClosure::BY_STAMP;
      loop.from_stamp = stamps_[e.from];
      loop.to_stamp = stamps_[e.to];
      loop_pub_.publish(loop);
      continue;
    }
    rrr_slam::FleetLoopClosure fleet_loop;
    const int a = RobotOf(e.from), b = RobotOf(e.to);
    fleet_loop.from_robot = options_.robots[a];
    fleet_loop.to_robot = options_.robots[b];
    loop.reference = rrr_slam::LoopClosure::BY_ID;
    loop.from_id = e.from - first_of_robot_[a];
    loop.to_id = e.to - first_of_robot_[b];
    fleet_loop.loop = loop;
    loop_pub_.publish(fleet_loop);
  }
  if (next_ > last_) {
    std_msgs::Bool done;
    done.data = true;
    done_pub_.publish(done);
  }
}

}  // namespace rrr_ros
