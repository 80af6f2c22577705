// One quantile of a growing sample, kept up to date as values arrive.
#ifndef RRR_RRR_MAP_RUNNING_QUANTILE_H_
#define RRR_RRR_MAP_RUNNING_QUANTILE_H_

#include <functional>
#include <queue>
#include <vector>

namespace rrr {

// The q-quantile of the values added so far by the nearest lower rank: the
// value at index ⌊q·(n − 1)⌋ of the n values sorted ascending. O(log n) per
// value added, O(1) to read.
class RunningQuantile {
 public:
  // 0 ≤ `q` ≤ 1.
  explicit RunningQuantile(double q) : q_(q) {}

  void Add(double value);
  int size() const { return static_cast<int>(lower_.size() + upper_.size()); }
  // The quantile; size() must be positive.
  double Value() const { return lower_.top(); }

 private:
  double q_;
  // The ⌊q·(n − 1)⌋ + 1 smallest values, the largest of them on top; the
  // rest, the smallest on top.
  std::priority_queue<double> lower_;
  std::priority_queue<double, std::vector<double>, std::greater<>> upper_;
};

}  // namespace rrr

#endif  // RRR_RRR_MAP_RUNNING_QUANTILE_H_
