#include "rrr/rrr/loop_scale_history.h"

#include <algorithm>

namespace rrr {

void LoopScaleHistory::ExtendTo(int poses, double value, int samples) {
  while (size() < poses) {
    values_.push_back(value);
    samples_.push_back(samples);
  }
}

void LoopScaleHistory::RecomputeFrom(
    int pose, std::vector<std::pair<int, double>> samples,
    const NoiseScaleEstimate& estimate) {
  std::stable_sort(
      samples.begin(), samples.end(),
      [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<double> before;  // D² of the loops that arrived by pose p
  size_t next = 0;
  double value = 1.0;
  for (int p = 0; p < size(); ++p) {
    const size_t had = before.size();
    while (next < samples.size() && samples[next].first <= p) {
      before.push_back(samples[next++].second);
    }
    if (p < pose) continue;
    if (p == pose || before.size() != had) {
      value = estimate.FromLoopSamples(before);
    }
    values_[p] = value;
    samples_[p] = static_cast<int>(before.size());
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
