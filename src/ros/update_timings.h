// How long rrr_node's updates take and how long candidates wait for them.
#ifndef RRR_ROS_UPDATE_TIMINGS_H_
#define RRR_ROS_UPDATE_TIMINGS_H_

#include <cstddef>
#include <vector>

namespace rrr_ros {

// Seconds of every update of the worker and every candidate's latency (from
// arrival to the publication of the update that took it in), summarized
// on request. Not thread-safe: the node copies it under its state lock and
// summarizes the copy.
class UpdateTimings {
 public:
  // The updates a "recent" maximum looks back over.
  static constexpr size_t kRecentUpdates = 100;

  struct Summary {
    double latency_p50 = 0, latency_p99 = 0, latency_max = 0;
    double update_p50 = 0, update_p99 = 0;
    double update_max = 0, recent_update_max = 0, last_update = 0;
  };

  void AddUpdate(double seconds) { update_seconds_.push_back(seconds); }
  void AddLatency(double seconds) { latencies_.push_back(seconds); }

  // Quantiles of what was added so far (0 where nothing was).
  Summary Summarize() const;

 private:
  std::vector<double> update_seconds_, latencies_;
};

}  // namespace rrr_ros

#endif  // RRR_ROS_UPDATE_TIMINGS_H_
