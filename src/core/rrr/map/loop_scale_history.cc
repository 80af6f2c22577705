#include "rrr/rrr/map/loop_scale_history.h"

#include <algorithm>
#include <stdexcept>

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

void LoopScaleHistory::Save(ByteWriter* out) const {
  std::vector<int> run_lengths;
  for (int p = 0; p < size(); ++p) {
    if (p > 0 && values_[p] == values_[p - 1] &&
        samples_[p] == samples_[p - 1]) {
      ++run_lengths.back();
    } else {
      run_lengths.push_back(1);
    }
  }
  out->Ints(run_lengths);
  int p = 0;
  for (const int length : run_lengths) {
    out->Double(values_[p]);
    out->Int(samples_[p]);
    p += length;
  }
}

void LoopScaleHistory::Restore(ByteReader* in) {
  for (const int length : in->Ints("loop scale runs")) {
    const double value = in->Double("a loop scale");
    const int samples = static_cast<int>(in->Int("a loop scale's samples"));
    if (length < 1) throw std::runtime_error("a loop scale run is empty");
    ExtendTo(size() + length, value, samples);
  }
}

}  // namespace rrr
