#include "rrr/rrr/map/running_quantile.h"

#include <cstddef>

namespace rrr {

void RunningQuantile::Add(double value) {
  if (lower_.empty() || value <= lower_.top()) {
    lower_.push(value);
  } else {
    upper_.push(value);
  }
  const auto wanted =
      static_cast<std::size_t>(q_ * static_cast<double>(size() - 1)) + 1;
  while (lower_.size() > wanted) {
    upper_.push(lower_.top());
    lower_.pop();
  }
  while (lower_.size() < wanted) {
    lower_.push(upper_.top());
    upper_.pop();
  }
}

}  // namespace rrr
