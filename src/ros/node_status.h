// What a node's users read of its state, kept where both of its threads
// reach it and served on ~get_status and /diagnostics.
#ifndef RRR_ROS_NODE_STATUS_H_
#define RRR_ROS_NODE_STATUS_H_

#include <ros/ros.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <vector>

#include "rrr_slam/GetStatus.h"
#include "update_timings.h"

namespace rrr_ros {

// The counters a node's worker keeps and the inputs its ROS threads
// received. Once Serve() is called, ~get_status answers Snapshot() and
// /diagnostics carries it every second (DiagnosticsOf).
class NodeStatus {
 public:
  // Fills the queue's fields of a snapshot (NodeWorker::SetQueueStatus).
  using QueueStatus = std::function<void(rrr_slam::GetStatus::Response*)>;

  // Advertises ~get_status on `private_nh` and /diagnostics on `nh`; a node
  // calls it once its state is built, so that no answer precedes it.
  void Serve(ros::NodeHandle& nh, ros::NodeHandle& private_nh,
             QueueStatus queue_status);
  // `counts` and `timings` copied under `mutex` (the timings summarized
  // outside it), with the queue's fields and the inputs received.
  rrr_slam::GetStatus::Response Snapshot();
  // Counts an invalid message and warns (throttled), naming it as `kind`
  // message `seq`, with `why`.
  void CountInvalid(const std::string& kind, uint32_t seq,
                    const std::string& why);
  // Counts an update the session database could not record (`why`: the
  // store's error; "" counts nothing) and logs it (throttled).
  void CountDatabaseError(const std::string& why);
  // The worker notes when each loop candidate it takes in arrived; the
  // update that publishes its state then adds its latency (under `mutex`)
  // with AddCandidateLatencies().
  void NoteCandidateArrival(std::chrono::steady_clock::time_point arrival);
  void AddCandidateLatencies();

  // The worker's counters and update timings, under `mutex`.
  std::mutex mutex;
  rrr_slam::GetStatus::Response counts;
  UpdateTimings timings;
  // Counted by the ROS threads as messages arrive.
  std::atomic<uint64_t> odometry_received{0}, loops_received{0};

 private:
  bool OnGetStatus(rrr_slam::GetStatus::Request& req,
                   rrr_slam::GetStatus::Response& res);
  void OnDiagnosticsTimer(const ros::TimerEvent& event);

  QueueStatus queue_status_;
  // Arrivals of the candidates taken in since the last update (worker).
  std::vector<std::chrono::steady_clock::time_point> unpublished_arrivals_;
  ros::ServiceServer status_srv_;
  ros::Publisher diagnostics_pub_;
  ros::Timer diagnostics_timer_;
};

}  // namespace rrr_ros

#endif  // RRR_ROS_NODE_STATUS_H_
