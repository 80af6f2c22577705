// Sparse Gauss–Newton over a pose graph with a subset of its loops active.
#ifndef RRR_SOLVER_GAUSS_NEWTON_H_
#define RRR_SOLVER_GAUSS_NEWTON_H_

#include <memory>
#include <vector>

#include "rrr/graph/pose_graph.h"
#include "rrr/solver/block_cholesky.h"
#include "rrr/solver/consistency_solver.h"

namespace rrr {

// When Optimize() stops.
struct ConvergenceOptions {
  int max_iterations = 100;
  // Stop when the error decreases by less than this fraction in a step.
  double relative_decrease = 1e-9;
};

// Gauss–Newton on the sparse normal equations, with the first pose (and any
// pose the graph marks fixed) held fixed. The sparsity pattern of odometry
// plus every loop candidate is analysed once at construction; every solve with
// any subset of loops active reuses it. The graph must outlive the solver and
// must not change while the solver exists.
template <class Pose>
class GaussNewton : public ConsistencySolver {
 public:
  // `iterations` is k, the number of iterations of each consistency Solve().
  GaussNewton(const PoseGraph<Pose>& graph, int iterations);
  ~GaussNewton() override;

  SubsetErrors Solve(const std::vector<int>& active_loops) override;
  int residual_dim() const override { return Pose::kDof; }

  // Runs Gauss–Newton from the odometry initial estimate with odometry and
  // `active_loops` until it converges; returns the estimates and sets
  // `*iterations_run` if given.
  std::vector<Pose> Optimize(const std::vector<int>& active_loops,
                             const ConvergenceOptions& options,
                             int* iterations_run = nullptr);

  // The odometry chain every solve starts from.
  const std::vector<Pose>& initial() const { return initial_; }
  // Errors of the given loops and odometry at estimates `x`.
  SubsetErrors Evaluate(const std::vector<int>& active_loops,
                        const std::vector<Pose>& x) const;

 private:
  struct EdgeSlots {
    int block_from, block_to;  // -1 for fixed poses
    int off_diagonal;          // slot, -1 if either pose is fixed
  };
  EdgeSlots SlotsOf(const Constraint<Pose>& edge) const;
  void Accumulate(const Constraint<Pose>& edge, const EdgeSlots& slots,
                  const std::vector<Pose>& x, Eigen::VectorXd* rhs);
  // One Gauss–Newton step; returns false if the system is not solvable.
  bool Step(const std::vector<int>& active_loops, std::vector<Pose>* x);

  const PoseGraph<Pose>& graph_;
  int iterations_;
  std::vector<Pose> initial_;
  std::vector<int> block_of_pose_;  // -1 for fixed poses
  std::unique_ptr<BlockCholesky<Pose::kDof>> system_;
  std::vector<EdgeSlots> odometry_slots_;
  std::vector<EdgeSlots> loop_slots_;
};

}  // namespace rrr

#endif  // RRR_SOLVER_GAUSS_NEWTON_H_
