// Grouping loop candidates into clusters of topologically related links.
#ifndef RRR_RRR_CLUSTERING_H_
#define RRR_RRR_CLUSTERING_H_

#include <cstdint>
#include <vector>

#include "rrr/graph/pose_graph.h"
#include "rrr/io/byte_stream.h"

namespace rrr {

// A cluster: loops that link one stretch of trajectory [start_low,
// start_high] (the later ends) to one earlier stretch [end_low, end_high],
// of one group (a pair of odometry chains: the ids of the two stretches
// count along their own chains).
struct Cluster {
  PoseId start_low, start_high, end_low, end_high;
  std::vector<int> loops;  // loop indices, in the order they joined
  bool closed = false;     // takes no more loops (Clustering::Close)
  std::int64_t group = 0;
};

// Assigns loops to clusters as they are added (RRR_ALGORITHM.md §1): a loop
// joins the first cluster (in creation order) of its group with a start
// bound and an end bound each closer than `window`, widening its ranges, or
// opens a new cluster. Closed clusters take no more loops.
class Clustering {
 public:
  explicit Clustering(PoseId window) : window_(window) {}
  // Adds loop `loop` of group `group` between the later end `start` and the
  // earlier end `end` (start = max(a, b), end = min(a, b) in one chain);
  // returns its cluster.
  int Add(int loop, PoseId start, PoseId end, std::int64_t group = 0);
  // Closes cluster `c`: later loops do not join it.
  void Close(int c) { clusters_.at(c).closed = true; }
  const std::vector<Cluster>& clusters() const { return clusters_; }

  // Writes the clusters; Restore reads them into a clustering of the same
  // window that has none, which then equals this one.
  void Save(ByteWriter* out) const;
  void Restore(ByteReader* in);

 private:
  // The layout Save writes and Restore reads (Self: const Clustering to
  // write, Clustering to read).
  template <class Stream, class Self>
  static void Transfer(Stream* io, Self* self);

  PoseId window_;
  std::vector<Cluster> clusters_;
};

// Clusters the loops whose end ids are `loop_ends[k]` (loop k) taken in
// ascending order of (a, b), as batch RRR does. Sets `cluster_of_loop`.
std::vector<Cluster> ClusterInBatchOrder(
    const std::vector<std::pair<PoseId, PoseId>>& loop_ends, PoseId window,
    std::vector<int>* cluster_of_loop);

}  // namespace rrr

#endif  // RRR_RRR_CLUSTERING_H_
