// The time stamps of keyframes, for loop candidates that name poses by time.
#ifndef RRR_GRAPH_KEYFRAME_STAMPS_H_
#define RRR_GRAPH_KEYFRAME_STAMPS_H_

#include <cstdint>
#include <vector>

namespace rrr {

// One stamp (nanoseconds) per keyframe, by pose index, never decreasing.
class KeyframeStamps {
 public:
  // What Find() returns for a stamp after the newest keyframe's: a keyframe
  // near it may still come.
  static constexpr int kNotYet = -2;
  // What Find() returns when no keyframe is within the tolerance.
  static constexpr int kNone = -1;

  // Find() matches stamps at most `tolerance_ns` away. Throws
  // std::invalid_argument if it is negative.
  explicit KeyframeStamps(std::int64_t tolerance_ns);

  // Appends the next keyframe's stamp. Throws std::invalid_argument if it is
  // older than the newest one.
  void Append(std::int64_t stamp_ns);
  // The pose index of the keyframe nearest to `stamp_ns` within the
  // tolerance (the later of two equally near), kNotYet if `stamp_ns` is
  // after the newest keyframe's, else kNone.
  int Find(std::int64_t stamp_ns) const;

  bool empty() const { return stamps_.empty(); }
  // The newest stamp; the container must not be empty.
  std::int64_t newest() const { return stamps_.back(); }
  const std::vector<std::int64_t>& stamps() const { return stamps_; }

 private:
  std::int64_t tolerance_ns_;
  std::vector<std::int64_t> stamps_;
};

}  // namespace rrr

#endif  // RRR_GRAPH_KEYFRAME_STAMPS_H_
