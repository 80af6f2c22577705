// RRR over time: poses, odometry and loop candidates arrive as the robot moves.
#ifndef RRR_RRR_PUBLISHED_INCREMENTAL_VERIFIER_H_
#define RRR_RRR_PUBLISHED_INCREMENTAL_VERIFIER_H_

#include <map>
#include <vector>

#include "rrr/graph/pose_graph.h"
#include "rrr/rrr/chi_square.h"
#include "rrr/rrr/clustering.h"
#include "rrr/rrr/online_verifier.h"
#include "rrr/rrr/options.h"
#include "rrr/solver/consistency_solver.h"

namespace rrr {

// Incremental RRR (RRR_ALGORITHM.md §4). Loop candidates are clustered as
// they arrive (all candidates seen so far, in the batch order); a cluster is
// ready once the robot has moved `cluster_window` poses past its latest loop,
// or at Finish(). Whenever the set of ready clusters changes, the decision
// procedure runs over all ready clusters, so earlier decisions can be
// reversed. After the last input, Finish() gives exactly the decisions of
// VerifyBatch on graph().
//
// A cluster's consistency solve depends only on the stretch of chain its
// loops span (see PoseGraphSolver), so its errors are computed once and reused
// as the chain grows; only the gate's edge count is brought up to date.
template <class Pose>
class IncrementalVerifier : public OnlineVerifier<Pose> {
 public:
  // Throws std::invalid_argument if `options` do not validate.
  explicit IncrementalVerifier(const RrrOptions& options);

  std::vector<DecisionChange> Update() override { return Judge(false); }
  std::vector<DecisionChange> Finish() override { return Judge(true); }
  // Odometry and the accepted loops, solved to convergence from odometry.
  std::vector<Pose> Map() override;
  int num_clusters() const override {
    return static_cast<int>(clusters_.size());
  }

 private:
  std::vector<DecisionChange> Judge(bool finish);

  RrrOptions options_;
  ChiSquareQuantile chi2_;
  std::vector<Cluster> clusters_;
  std::vector<std::vector<int>> judged_;  // ready clusters of the last run
  // Errors of each cluster's own solve, by its member loops.
  std::map<std::vector<int>, SubsetErrors> intra_errors_;
};

}  // namespace rrr

#endif  // RRR_RRR_PUBLISHED_INCREMENTAL_VERIFIER_H_
