// One quantile of a sample, kept up to date as values arrive and leave.
#ifndef RRR_RRR_MAP_RUNNING_QUANTILE_H_
#define RRR_RRR_MAP_RUNNING_QUANTILE_H_

#include <set>

#include "rrr/io/byte_stream.h"

namespace rrr {

// The q-quantile of the values added so far by the nearest lower rank: the
// value at index ⌊q·(n − 1)⌋ of the n values sorted ascending. O(log n) per
// value added or removed, O(1) to read.
class RunningQuantile {
 public:
  // 0 ≤ `q` ≤ 1.
  explicit RunningQuantile(double q) : q_(q) {}

  // O(log n).
  void Add(double value);
  // Removes one value equal to `value`; returns false (and changes nothing)
  // if there is none. O(log n).
  bool Remove(double value);
  int size() const { return static_cast<int>(lower_.size() + upper_.size()); }
  // The quantile; size() must be positive.
  double Value() const { return *lower_.rbegin(); }

  // Writes the values; Restore reads them into a quantile that has none,
  // which then equals this one.
  void Save(ByteWriter* out) const;
  void Restore(ByteReader* in);

 private:
  // Moves values between the halves until `lower_` holds ⌊q·(n − 1)⌋ + 1.
  void Balance();

  double q_;
  // The ⌊q·(n − 1)⌋ + 1 smallest values, and the rest.
  std::multiset<double> lower_, upper_;
};

}  // namespace rrr

#endif  // RRR_RRR_MAP_RUNNING_QUANTILE_H_
