#include "rrr/rrr/clustering.h"

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <numeric>

namespace rrr {
namespace {

bool Near(PoseId x, PoseId low, PoseId high, PoseId window) {
  return std::llabs(x - low) < window || std::llabs(x - high) < window;
}

}  // namespace

int Clustering::Add(int loop, PoseId start, PoseId end, std::int64_t group) {
  for (size_t c = 0; c < clusters_.size(); ++c) {
    Cluster& cl = clusters_[c];
    if (!cl.closed && cl.group == group &&
        Near(start, cl.start_low, cl.start_high, window_) &&
        Near(end, cl.end_low, cl.end_high, window_)) {
      cl.start_low = std::min(cl.start_low, start);
      cl.start_high = std::max(cl.start_high, start);
      cl.end_low = std::min(cl.end_low, end);
      cl.end_high = std::max(cl.end_high, end);
      cl.loops.push_back(loop);
      return static_cast<int>(c);
    }
  }
  clusters_.push_back(Cluster{start, start, end, end, {loop}, false, group});
  return static_cast<int>(clusters_.size()) - 1;
}

template <class Stream, class Self>
void Clustering::Transfer(Stream* io, Self* self) {
  io->Size(&self->clusters_, 7 * sizeof(std::int64_t), "clusters");
  for (auto& c : self->clusters_) {
    for (auto* id : {&c.start_low, &c.start_high, &c.end_low, &c.end_high}) {
      io->Field(id, "a cluster's bounds");
    }
    io->Field(&c.group, "a cluster's group");
    io->Field(&c.loops, "a cluster's loops");
    io->Field(&c.closed, "whether a cluster is closed");
  }
}

void Clustering::Save(ByteWriter* out) const { Transfer(out, this); }

void Clustering::Restore(ByteReader* in) { Transfer(in, this); }

std::vector<Cluster> ClusterInBatchOrder(
    const std::vector<std::pair<PoseId, PoseId>>& loop_ends, PoseId window,
    std::vector<int>* cluster_of_loop) {
  std::vector<int> order(loop_ends.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int x, int y) { return loop_ends[x] < loop_ends[y]; });
  Clustering clustering(window);
  cluster_of_loop->assign(loop_ends.size(), -1);
  for (const int k : order) {
    const auto [a, b] = loop_ends[k];
    (*cluster_of_loop)[k] = clustering.Add(k, std::max(a, b), std::min(a, b));
  }
  return clustering.clusters();
}

}  // namespace rrr
