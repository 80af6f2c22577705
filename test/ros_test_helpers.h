// Small helpers of the rostest tests: waiting and service calls.
#ifndef RRR_TEST_ROS_TEST_HELPERS_H_
#define RRR_TEST_ROS_TEST_HELPERS_H_

#include <ros/ros.h>

#include <functional>
#include <string>

#include "rrr_slam/Decisions.h"
#include "rrr_slam/Finish.h"
#include "rrr_slam/GetStatus.h"

namespace rrr_test {

// Spins until `done()` or `seconds` of wall time pass; returns done().
inline bool WaitFor(const std::function<bool()>& done, double seconds) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(seconds);
  while (!done() && ros::WallTime::now() < end && ros::ok()) {
    ros::spinOnce();
    ros::WallDuration(0.01).sleep();
  }
  return done();
}

inline rrr_slam::GetStatus::Response Status() {
  rrr_slam::GetStatus srv;
  ros::service::call("/rrr_node/get_status", srv);
  return srv.response;
}

// Calls ~finish and waits (spinning) until `*decisions`, kept up to date by
// a subscriber of ~decisions, has all `candidates` decided; true if so.
inline bool FinishAndWait(const rrr_slam::Decisions::ConstPtr* decisions,
                          size_t candidates) {
  rrr_slam::Finish finish;
  if (!ros::service::call("/rrr_node/finish", finish)) return false;
  return WaitFor(
      [&] {
        return *decisions && (*decisions)->pending == 0 &&
               (*decisions)->decisions.size() == candidates;
      },
      30.0);
}

}  // namespace rrr_test

#endif  // RRR_TEST_ROS_TEST_HELPERS_H_
