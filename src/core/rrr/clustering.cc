#include "rrr/rrr/clustering.h"

#include <algorithm>
#include <cstdlib>

namespace rrr {
namespace {

bool Near(PoseId x, PoseId low, PoseId high, PoseId window) {
  return std::llabs(x - low) < window || std::llabs(x - high) < window;
}

}  // namespace

int Clustering::Add(int loop, PoseId a, PoseId b) {
  const PoseId start = std::max(a, b), end = std::min(a, b);
  for (size_t c = 0; c < clusters_.size(); ++c) {
    Cluster& cl = clusters_[c];
    if (Near(start, cl.start_low, cl.start_high, window_) &&
        Near(end, cl.end_low, cl.end_high, window_)) {
      cl.start_low = std::min(cl.start_low, start);
      cl.start_high = std::max(cl.start_high, start);
      cl.end_low = std::min(cl.end_low, end);
      cl.end_high = std::max(cl.end_high, end);
      cl.loops.push_back(loop);
      return static_cast<int>(c);
    }
  }
  clusters_.push_back(Cluster{start, start, end, end, {loop}});
  return static_cast<int>(clusters_.size()) - 1;
}

}  // namespace rrr
