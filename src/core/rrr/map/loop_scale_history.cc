#include "rrr/rrr/map/loop_scale_history.h"

#include <algorithm>

namespace rrr {

void LoopScaleHistory::ExtendTo(int poses, double value, int samples) {
  while (size() < poses) {
    values_.push_back(value);
    samples_.push_back(samples);
  }
}

void LoopScaleHistory::RecomputeFrom(
    int pose, std::vector<std::pair<int, double>> samples, int residual_dim) {
  std::stable_sort(
      samples.begin(), samples.end(),
      [](const auto& a, const auto& b) { return a.first < b.first; });
  NoiseScaleEstimate before(residual_dim);  // the loops that arrived by p
  size_t next = 0;
  for (int p = 0; p < size(); ++p) {
    while (next < samples.size() && samples[next].first <= p) {
      before.AddLoopSample(samples[next++].second);
    }
    if (p < pose) continue;
    values_[p] = before.FromLoops();
    samples_[p] = before.num_loop_samples();
  }
}

double LoopScaleHistory::At(int pose) const {
  if (values_.empty()) return 1.0;
  return values_[std::min(std::max(pose, 0), size() - 1)];
}

int LoopScaleHistory::FirstWith(int samples) const {
  const auto known =
      std::lower_bound(samples_.begin(), samples_.end(), samples);
  return known == samples_.end() ? -1
                                 : static_cast<int>(known - samples_.begin());
}

}  // namespace rrr
