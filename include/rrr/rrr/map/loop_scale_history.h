// The loops' noise-scale estimate as it stood at each pose.
#ifndef RRR_RRR_MAP_LOOP_SCALE_HISTORY_H_
#define RRR_RRR_MAP_LOOP_SCALE_HISTORY_H_

#include <utility>
#include <vector>

#include "rrr/io/byte_stream.h"
#include "rrr/rrr/map/noise_scale.h"

namespace rrr {

// Per pose index p: the estimate NoiseScaleEstimate::FromLoops from the loops
// that arrived before pose p existed, and their number. A decision made at
// pose p uses the entry of p, so it does not depend on when it is made.
class LoopScaleHistory {
 public:
  int size() const { return static_cast<int>(values_.size()); }

  // Records `value`, from `samples` loop samples, for every pose index from
  // size() to `poses` - 1 (nothing if `poses` <= size()).
  void ExtendTo(int poses, double value, int samples);
  // Computes every entry from pose index `pose` on again from `samples`,
  // each (poses at its arrival, D² of the loop alone), as
  // NoiseScaleEstimate(`residual_dim`).FromLoops() after those that arrived
  // by then: for when samples arrived late, with a pose already recorded.
  void RecomputeFrom(int pose, std::vector<std::pair<int, double>> samples,
                     int residual_dim);
  // The estimate at pose index `pose`, clamped to the recorded poses; 1 (the
  // information matrices as given) if none is recorded.
  double At(int pose) const;
  // The first pose index whose entry counts at least `samples` loop samples,
  // or -1 if none does yet.
  int FirstWith(int samples) const;

  // Writes the entries (as runs of equal ones); Restore reads them into a
  // history that has none, which then equals this one.
  void Save(ByteWriter* out) const;
  void Restore(ByteReader* in);

 private:
  std::vector<double> values_;
  std::vector<int> samples_;  // non-decreasing
};

}  // namespace rrr

#endif  // RRR_RRR_MAP_LOOP_SCALE_HISTORY_H_
