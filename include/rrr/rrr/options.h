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

  // Returns an empty string if the options are usable, otherwise a message
  // naming the first bad option.
  std::string Validate() const;
};

}  // namespace rrr

#endif  // RRR_RRR_OPTIONS_H_
