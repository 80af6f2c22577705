#include "rrr/graph/keyframe_stamps.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace rrr {

KeyframeStamps::KeyframeStamps(std::int64_t tolerance_ns)
    : tolerance_ns_(tolerance_ns) {
  if (tolerance_ns < 0) {
    throw std::invalid_argument(
        "the stamp tolerance must not be negative, got " +
        std::to_string(tolerance_ns) + " ns");
  }
}

void KeyframeStamps::Append(std::int64_t stamp_ns) {
  if (!stamps_.empty() && stamp_ns < stamps_.back()) {
    throw std::invalid_argument("keyframe stamp " + std::to_string(stamp_ns) +
                                " ns is older than the newest, " +
                                std::to_string(stamps_.back()) + " ns");
  }
  stamps_.push_back(stamp_ns);
}

int KeyframeStamps::Find(std::int64_t stamp_ns) const {
  if (stamps_.empty() || stamp_ns > stamps_.back()) return kNotYet;
  const auto after = std::lower_bound(stamps_.begin(), stamps_.end(), stamp_ns);
  int best = kNone;
  std::int64_t best_gap = tolerance_ns_;
  for (const auto candidate : {after - 1, after}) {
    if (candidate < stamps_.begin() || candidate >= stamps_.end()) continue;
    const std::int64_t gap =
        candidate < after ? stamp_ns - *candidate : *candidate - stamp_ns;
    if (gap <= best_gap) {
      best_gap = gap;
      best = static_cast<int>(candidate - stamps_.begin());
    }
  }
  return best;
}

}  // namespace rrr
