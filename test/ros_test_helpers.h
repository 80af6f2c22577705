// Small helpers of the rostest tests: waiting and service calls.
#ifndef RRR_TEST_ROS_TEST_HELPERS_H_
#define RRR_TEST_ROS_TEST_HELPERS_H_

#include <ros/ros.h>

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "rrr_slam/Decisions.h"
#include "rrr_slam/Finish.h"
#include "rrr_slam/GetDecisions.h"
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

// Every candidate's state as ~decisions tells it: its messages applied in
// order, each carrying the candidates that changed or are new. A gap in the
// messages' header.seq (one was missed) is counted.
class DecisionTable {
 public:
  // Subscribes to ~decisions with a queue that keeps every message.
  explicit DecisionTable(ros::NodeHandle& nh)
      : sub_(nh.subscribe<rrr_slam::Decisions>(
            "/rrr_node/decisions", 100000,
            [this](const rrr_slam::Decisions::ConstPtr& m) { Apply(*m); })) {}

  void Apply(const rrr_slam::Decisions& m) {
    if (have_last_ && m.header.seq != last_.header.seq + 1) ++gaps_;
    for (const auto& d : m.decisions) by_candidate_[d.candidate] = d;
    last_ = m;
    have_last_ = true;
  }
  // Whether the last message says that `candidates` exist, none pending,
  // and every one of them has been carried.
  bool AllDecided(size_t candidates) const {
    return have_last_ && last_.pending == 0 && last_.candidates == candidates &&
           by_candidate_.size() == candidates;
  }
  std::vector<rrr_slam::LoopDecision> decisions() const {
    std::vector<rrr_slam::LoopDecision> out;
    for (const auto& [c, d] : by_candidate_) out.push_back(d);
    return out;
  }
  const rrr_slam::Decisions& last() const { return last_; }
  int gaps() const { return gaps_; }

 private:
  ros::Subscriber sub_;
  std::map<uint32_t, rrr_slam::LoopDecision> by_candidate_;
  rrr_slam::Decisions last_;
  bool have_last_ = false;
  int gaps_ = 0;
};

// ~get_decisions: every candidate's state now.
inline rrr_slam::Decisions Snapshot() {
  rrr_slam::GetDecisions srv;
  ros::service::call("/rrr_node/get_decisions", srv);
  return srv.response.decisions;
}

// Calls ~finish (every pending cluster judged) and returns ~get_decisions
// then; its `full` is false if a call failed.
inline rrr_slam::Decisions FinishAndSnapshot() {
  rrr_slam::Finish finish;
  if (!ros::service::call("/rrr_node/finish", finish)) return {};
  return Snapshot();
}

// Whether `table` holds exactly the candidates and states of `snapshot`.
inline bool SameDecisions(const DecisionTable& table,
                          const rrr_slam::Decisions& snapshot) {
  const auto carried = table.decisions();
  if (!snapshot.full || carried.size() != snapshot.decisions.size()) {
    return false;
  }
  for (size_t k = 0; k < carried.size(); ++k) {
    const auto& a = carried[k];
    const auto& b = snapshot.decisions[k];
    if (a.candidate != b.candidate || a.state != b.state ||
        a.from_id != b.from_id || a.to_id != b.to_id ||
        a.cluster != b.cluster || a.waiting != b.waiting) {
      return false;
    }
  }
  return true;
}

}  // namespace rrr_test

#endif  // RRR_TEST_ROS_TEST_HELPERS_H_
