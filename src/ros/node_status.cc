#include "node_status.h"

#include <diagnostic_msgs/DiagnosticArray.h>

#include <utility>

#include "status_messages.h"

namespace rrr_ros {

void NodeStatus::Serve(ros::NodeHandle& nh, ros::NodeHandle& private_nh,
                       QueueStatus queue_status) {
  queue_status_ = std::move(queue_status);
  status_srv_ =
      private_nh.advertiseService("get_status", &NodeStatus::OnGetStatus, this);
  diagnostics_pub_ =
      nh.advertise<diagnostic_msgs::DiagnosticArray>("/diagnostics", 10);
  diagnostics_timer_ =
      nh.createTimer(ros::Duration(1.0), &NodeStatus::OnDiagnosticsTimer, this);
}

void NodeStatus::NoteCandidateArrival(
    std::chrono::steady_clock::time_point arrival) {
  unpublished_arrivals_.push_back(arrival);
}

void NodeStatus::AddCandidateLatencies() {
  const auto published = std::chrono::steady_clock::now();
  for (const auto& arrival : unpublished_arrivals_) {
    timings.AddLatency(
        std::chrono::duration<double>(published - arrival).count());
  }
  unpublished_arrivals_.clear();
}

rrr_slam::GetStatus::Response NodeStatus::Snapshot() {
  rrr_slam::GetStatus::Response out;
  UpdateTimings now;
  {
    std::lock_guard<std::mutex> lock(mutex);
    out = counts;
    now = timings;
  }
  const UpdateTimings::Summary t = now.Summarize();
  out.candidate_latency_p50 = t.latency_p50;
  out.candidate_latency_p99 = t.latency_p99;
  out.candidate_latency_max = t.latency_max;
  out.update_seconds_p50 = t.update_p50;
  out.update_seconds_p99 = t.update_p99;
  out.max_update_seconds = t.update_max;
  out.recent_max_update_seconds = t.recent_update_max;
  out.last_update_seconds = t.last_update;
  if (queue_status_) queue_status_(&out);
  out.odometry_received = odometry_received;
  out.loop_closures_received = loops_received;
  return out;
}

void NodeStatus::CountInvalid(const std::string& kind, uint32_t seq,
                              const std::string& why) {
  uint64_t count;
  {
    std::lock_guard<std::mutex> lock(mutex);
    count = ++counts.invalid_messages;
  }
  ROS_WARN_THROTTLE(
      5.0, "rrr_node: ignored %s message %u: %s (%lu invalid messages so far)",
      kind.c_str(), seq, why.c_str(), static_cast<unsigned long>(count));
}

void NodeStatus::CountDatabaseError(const std::string& why) {
  if (why.empty()) return;
  {
    std::lock_guard<std::mutex> lock(mutex);
    ++counts.database_errors;
  }
  ROS_ERROR_THROTTLE(5.0, "rrr_node: cannot record the update: %s",
                     why.c_str());
}

bool NodeStatus::OnGetStatus(rrr_slam::GetStatus::Request&,
                             rrr_slam::GetStatus::Response& res) {
  res = Snapshot();
  return true;
}

void NodeStatus::OnDiagnosticsTimer(const ros::TimerEvent&) {
  diagnostics_pub_.publish(
      DiagnosticsOf(Snapshot(), ros::this_node::getName()));
}

}  // namespace rrr_ros
