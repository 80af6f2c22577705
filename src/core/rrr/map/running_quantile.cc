#include "rrr/rrr/map/running_quantile.h"

#include <cstddef>
#include <iterator>

namespace rrr {

void RunningQuantile::Add(double value) {
  if (lower_.empty() || value <= *lower_.rbegin()) {
    lower_.insert(value);
  } else {
    upper_.insert(value);
  }
  Balance();
}

bool RunningQuantile::Remove(double value) {
  auto it = lower_.find(value);
  if (it != lower_.end()) {
    lower_.erase(it);
  } else {
    it = upper_.find(value);
    if (it == upper_.end()) return false;
    upper_.erase(it);
  }
  Balance();
  return true;
}

void RunningQuantile::Save(ByteWriter* out) const {
  out->Int(size());
  for (const auto* half : {&lower_, &upper_}) {
    for (const double v : *half) out->Double(v);
  }
}

void RunningQuantile::Restore(ByteReader* in) {
  const size_t n = in->Count("quantile values", sizeof(double));
  for (size_t k = 0; k < n; ++k) Add(in->Double("a quantile value"));
}

void RunningQuantile::Balance() {
  const std::size_t wanted =
      size() == 0
          ? 0
          : static_cast<std::size_t>(q_ * static_cast<double>(size() - 1)) + 1;
  while (lower_.size() > wanted) {
    const auto largest = std::prev(lower_.end());
    upper_.insert(*largest);
    lower_.erase(largest);
  }
  while (lower_.size() < wanted) {
    lower_.insert(*upper_.begin());
    upper_.erase(upper_.begin());
  }
}

}  // namespace rrr
