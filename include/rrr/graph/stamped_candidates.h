// Loop candidates that name their poses by time stamp, held until keyframes
// near both stamps exist.
#ifndef RRR_GRAPH_STAMPED_CANDIDATES_H_
#define RRR_GRAPH_STAMPED_CANDIDATES_H_

#include <cstdint>
#include <utility>
#include <vector>

#include "rrr/graph/keyframe_stamps.h"

namespace rrr {

// Candidates of type T (e.g. a loop-closure message), each with the stamps
// (ns) of its two poses, in arrival order; at most `capacity` at once.
template <class T>
class StampedCandidates {
 public:
  explicit StampedCandidates(int capacity) : capacity_(capacity) {}

  int size() const { return static_cast<int>(held_.size()); }
  bool full() const { return size() >= capacity_; }

  // Holds `candidate` between the keyframes at `from_ns` and `to_ns`.
  // Returns false, holding nothing, if `capacity` candidates wait already.
  bool Hold(std::int64_t from_ns, std::int64_t to_ns, T candidate) {
    if (full()) return false;
    held_.push_back({from_ns, to_ns, std::move(candidate)});
    return true;
  }

  // Takes out every held candidate whose two stamps `stamps` can judge now
  // (KeyframeStamps::Find is not kNotYet for either), in arrival order:
  // `found`(from, to, candidate) with the keyframes' pose indices when both
  // have one within the tolerance, else `missing`(end, candidate) with
  // `end` "from" or "to", the first stamp without one. The others stay.
  template <class Found, class Missing>
  void Resolve(const KeyframeStamps& stamps, Found found, Missing missing) {
    ResolveWith(
        [&](std::int64_t stamp_ns, const char*, const T&) {
          return static_cast<std::int64_t>(stamps.Find(stamp_ns));
        },
        found, missing);
  }
  // As Resolve(), with `find`(stamp_ns, end, candidate) the keyframe of each
  // end ("from", "to"), or KeyframeStamps::kNotYet or kNone.
  template <class Find, class Found, class Missing>
  void ResolveWith(Find find, Found found, Missing missing) {
    auto keep = held_.begin();
    for (auto& h : held_) {
      const std::int64_t from = find(h.from_ns, "from", h.candidate);
      const std::int64_t to = find(h.to_ns, "to", h.candidate);
      if (from == KeyframeStamps::kNotYet || to == KeyframeStamps::kNotYet) {
        if (&*keep != &h) *keep = std::move(h);  // not onto itself
        ++keep;
      } else if (from < 0 || to < 0) {
        missing(from < 0 ? "from" : "to", h.candidate);
      } else {
        found(from, to, h.candidate);
      }
    }
    held_.erase(keep, held_.end());
  }

 private:
  struct Held {
    std::int64_t from_ns, to_ns;
    T candidate;
  };
  int capacity_;
  std::vector<Held> held_;
};

}  // namespace rrr

#endif  // RRR_GRAPH_STAMPED_CANDIDATES_H_
