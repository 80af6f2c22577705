// Gauss–Newton on a chosen part of a pose graph.
#ifndef RRR_SOLVER_LOCAL_PROBLEM_H_
#define RRR_SOLVER_LOCAL_PROBLEM_H_

#include <memory>
#include <vector>

#include "rrr/graph/pose_graph.h"
#include "rrr/solver/convergence.h"

namespace rrr {

template <int D>
class BlockCholesky;

// The least-squares problem of some edges over some free poses; every other
// pose an edge touches is held at its current estimate. The sparsity pattern
// is ordered and analysed once, at construction; each step refactorizes it
// numerically. The edges must outlive the problem.
template <class Pose>
class LocalProblem {
 public:
  using Edge = Constraint<Pose>;

  // `free` lists distinct pose indices in [0, num_poses); `edges` are the
  // problem's constraints, each between poses in [0, num_poses).
  LocalProblem(int num_poses, const std::vector<int>& free,
               std::vector<const Edge*> edges);
  ~LocalProblem();
  LocalProblem(const LocalProblem&) = delete;
  LocalProblem& operator=(const LocalProblem&) = delete;

  int num_free() const { return static_cast<int>(free_.size()); }
  const std::vector<int>& free() const { return free_; }
  const std::vector<const Edge*>& edges() const { return edges_; }

  // Multiplies each edge's information by its weight (in the order of
  // edges(); every weight 1 until set). Throws std::invalid_argument if the
  // count differs from the edges'.
  void SetWeights(std::vector<double> weights);

  // One Gauss–Newton step on the free poses of `x` (every pose of the
  // graph). Returns false, leaving `x` unchanged, if the linear system is not
  // positive definite.
  bool Step(std::vector<Pose>* x);
  // Steps until the error decreases by less than the relative threshold or
  // `options.max_iterations` steps were made. A step that would increase the
  // error is not taken (and ends the minimization as converged).
  MinimizeResult Minimize(std::vector<Pose>* x,
                          const ConvergenceOptions& options);
  // Σ w rᵀ Ω r over the problem's edges at `x` (w: their weights).
  double Chi2(const std::vector<Pose>& x) const;

 private:
  static constexpr int D = Pose::kDof;
  struct Slots {
    int from, to;      // blocks, -1 for poses held fixed
    int off_diagonal;  // -1 if either pose is held fixed
  };

  std::vector<int> free_;
  std::vector<int> block_of_pose_;  // -1 for poses held fixed
  std::vector<const Edge*> edges_;
  std::vector<double> weights_;  // empty: all 1
  std::vector<Slots> slots_;
  std::unique_ptr<BlockCholesky<D>> system_;
};

}  // namespace rrr

#endif  // RRR_SOLVER_LOCAL_PROBLEM_H_
