#include "update_timings.h"

#include <algorithm>

namespace rrr_ros {
namespace {

// The q-quantile (nearest rank below) of `values`, 0 if empty.
double Quantile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  const auto k = static_cast<size_t>(q * (values.size() - 1));
  std::nth_element(values.begin(), values.begin() + k, values.end());
  return values[k];
}

}  // namespace

UpdateTimings::Summary UpdateTimings::Summarize() const {
  Summary s;
  s.latency_p50 = Quantile(latencies_, 0.50);
  s.latency_p99 = Quantile(latencies_, 0.99);
  s.latency_max = Quantile(latencies_, 1.0);
  s.update_p50 = Quantile(update_seconds_, 0.50);
  s.update_p99 = Quantile(update_seconds_, 0.99);
  s.update_max = Quantile(update_seconds_, 1.0);
  if (!update_seconds_.empty()) {
    s.last_update = update_seconds_.back();
    s.recent_update_max =
        *std::max_element(update_seconds_.end() -
                              std::min(update_seconds_.size(), kRecentUpdates),
                          update_seconds_.end());
  }
  return s;
}

}  // namespace rrr_ros
