// RRR over time: poses, odometry and loop candidates arrive as the robot moves.
#ifndef RRR_RRR_INCREMENTAL_VERIFIER_H_
#define RRR_RRR_INCREMENTAL_VERIFIER_H_

#include <map>
#include <vector>

#include "rrr/graph/pose_graph.h"
#include "rrr/rrr/chi_square.h"
#include "rrr/rrr/clustering.h"
#include "rrr/rrr/options.h"
#include "rrr/solver/consistency_solver.h"

namespace rrr {

enum class LoopState { kPending, kAccepted, kRejected };
const char* ToString(LoopState state);

// A candidate whose state changed in an update.
struct DecisionChange {
  int candidate;  // candidate number, in arrival order
  LoopState previous;
  LoopState current;
};

// Incremental RRR (RRR_ALGORITHM.md §4). Loop candidates are clustered as
// they arrive (all candidates seen so far, in the batch order); a cluster is
// ready once the robot has moved `cluster_window` poses past its latest loop,
// or at Finish(). Whenever the set of ready clusters changes, the decision
// procedure runs over all ready clusters, so earlier decisions can be
// reversed. After the last input, Finish() gives exactly the decisions of
// VerifyBatch on graph().
//
// A cluster's consistency solve depends only on the stretch of chain its
// loops span (see GaussNewton), so its errors are computed once and reused
// as the chain grows; only the gate's edge count is brought up to date.
template <class Pose>
class IncrementalVerifier {
 public:
  using Information = typename Constraint<Pose>::Information;

  // Throws std::invalid_argument if `options` do not validate.
  explicit IncrementalVerifier(const RrrOptions& options);

  // Starts the chain at pose `id`. Throws std::logic_error if it has started.
  void AddFirstPose(PoseId id, const Pose& pose);
  // Appends the pose with the next id (last id + 1), reached from the last
  // pose by odometry `z`. Throws std::logic_error before AddFirstPose.
  // Returns the new pose's id.
  PoseId AddOdometry(const Pose& z, const Information& information);
  // Adds the candidate z ≈ x_a⁻¹ · x_b and returns its number (0, 1, ... in
  // arrival order). If a pose does not exist yet, the candidate waits for it.
  // Throws std::invalid_argument if |a - b| < 2 or a pose precedes the first
  // pose (it can never exist).
  int AddLoop(PoseId a, PoseId b, const Pose& z,
              const Information& information);

  // Judges the clusters that became ready; returns the changed decisions.
  std::vector<DecisionChange> Update();
  // Judges every cluster now, as at the end of a run; returns the changes.
  std::vector<DecisionChange> Finish();

  const PoseGraph<Pose>& graph() const { return graph_; }
  int num_candidates() const { return static_cast<int>(candidates_.size()); }
  // Candidates waiting for a pose that does not exist yet.
  int num_waiting() const { return static_cast<int>(waiting_.size()); }
  int num_clusters() const { return static_cast<int>(clusters_.size()); }
  LoopState state(int candidate) const {
    return candidates_.at(candidate).state;
  }
  // The candidate's cluster, or -1 while it waits for a pose.
  int cluster_of(int candidate) const;
  // The candidate's loop index in graph().loops(), or -1 while it waits.
  int loop_of(int candidate) const { return candidates_.at(candidate).loop; }
  // The candidates' end ids as given to AddLoop.
  std::pair<PoseId, PoseId> ends_of(int candidate) const;
  // Loop indices of the accepted candidates, ascending.
  std::vector<int> AcceptedLoops() const;
  // Number of consistency solves run so far.
  int num_solves() const { return num_solves_; }

 private:
  struct Candidate {
    PoseId a, b;
    Pose measurement;
    Information information;
    int loop = -1;
    LoopState state = LoopState::kPending;
  };
  void ApplyWaiting();
  std::vector<DecisionChange> Judge(bool finish);

  RrrOptions options_;
  ChiSquareQuantile chi2_;
  PoseGraph<Pose> graph_;
  std::vector<Candidate> candidates_;
  std::vector<int> waiting_;            // candidate numbers
  std::vector<int> candidate_of_loop_;  // graph loop index -> candidate
  std::vector<Cluster> clusters_;
  std::vector<int> cluster_of_loop_;
  std::vector<std::vector<int>> judged_;  // ready clusters of the last run
  // Errors of each cluster's own solve, by its member loops.
  std::map<std::vector<int>, SubsetErrors> intra_errors_;
  int num_solves_ = 0;
};

}  // namespace rrr

#endif  // RRR_RRR_INCREMENTAL_VERIFIER_H_
