// Parameters of RRR.
#ifndef RRR_RRR_OPTIONS_H_
#define RRR_RRR_OPTIONS_H_

#include <string>

namespace rrr {

struct RrrOptions {
  // t: loops whose ends are closer than this many poses may share a cluster.
  // 10 suits keyframe graphs; 50 suits Bicocca 25b (5 Hz odometry, 1 Hz loops).
  int cluster_window = 10;
  // k: Gauss–Newton iterations of each consistency test.
  int iterations = 4;
  // α: the χ² quantile of every gate.
  double alpha = 0.95;
  // Off (the method as published): the total error D²_G of a solve is gated
  // by χ²(α, e·n_G) over every edge of the graph. On: by χ²(α, e·n_S) over
  // the n_S edges that can carry error (the stretch of odometry the active
  // loops span, and the loops; see SubsetErrors), so a cluster that bends a
  // short stretch of odometry far is not let through by the many edges
  // elsewhere that it leaves untouched. Not part of the paper; measured in
  // BENCHMARKS.md.
  bool span_gate = false;
  // How many consistency solves may run at once. Decisions do not depend on
  // it: the intra-cluster tests run side by side, and the inter-cluster
  // procedure solves ahead (at most 4 joint solves at once) the sets it would
  // reach by setting aside clusters in their current order of inconsistency,
  // using only the solves the one-at-a-time procedure would have made.
  int threads = 1;

  // Returns an empty string if the options are usable, otherwise a message
  // naming the first bad option.
  std::string Validate() const;
};

}  // namespace rrr

#endif  // RRR_RRR_OPTIONS_H_
