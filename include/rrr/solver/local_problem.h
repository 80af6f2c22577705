// Gauss–Newton and Levenberg–Marquardt on a chosen part of a pose graph.
#ifndef RRR_SOLVER_LOCAL_PROBLEM_H_
#define RRR_SOLVER_LOCAL_PROBLEM_H_

#include <Eigen/Core>
#include <limits>
#include <memory>
#include <vector>

#include "rrr/graph/pose_graph.h"
#include "rrr/solver/convergence.h"

namespace rrr {

template <int D>
class BlockCholesky;

// The state of Levenberg–Marquardt minimization, carried from one iteration
// to the next: steps solve (H + damping·S) δ = −g with S = diag(H), which
// makes them independent of the units of each pose coordinate and of any
// common scale of the information matrices. The damping starts at 0: plain
// Gauss–Newton steps are taken while they decrease the error, and from the
// first that does not, the damping follows Nielsen's rule (as in Ceres and
// g2o): raised after each failed step, lowered after good ones, and back to
// 0 once below kLeastDamping.
struct TrustRegion {
  static constexpr double kFirstDamping = 1e-4;
  static constexpr double kLeastDamping = 1e-10;
  double damping = 0.0;
  double growth = 2.0;  // the factor of the next rise (doubles per failure)
  // Below this relative decrease of the error a step counts as none.
  double relative_decrease = 1e-9;
  // Set by StepWithin when it returns kNoDecrease: whether the linear model
  // predicted too small a decrease (else no damped step lowered the error).
  bool stationary = false;
};

// What one Levenberg–Marquardt iteration did.
enum class StepOutcome {
  kTaken,       // a step decreased the error
  kNoDecrease,  // no step can decrease the error by relative_decrease
                // (x unchanged: a minimum to that precision)
  kNotSolved,   // no damped system could be solved (x unchanged)
};

// The least-squares problem of some edges over some free poses; every other
// pose an edge touches is held at its current estimate. The sparsity pattern
// is ordered and analysed once, at construction; each step refactorizes it
// numerically. The edges must outlive the problem.
template <class Pose>
class LocalProblem {
 public:
  using Edge = Constraint<Pose>;

  // `free` lists distinct pose indices in [0, num_poses); `edges` are the
  // problem's constraints, each between poses in [0, num_poses). Edges from
  // `weighed` on (all by default) are probes: always of weight 0, they are
  // not in the Gauss–Newton matrix's pattern (ChangesOfMinimum of groups
  // out costs no fill-in).
  LocalProblem(int num_poses, const std::vector<int>& free,
               std::vector<const Edge*> edges,
               size_t weighed = static_cast<size_t>(-1));
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
  // One Levenberg–Marquardt iteration (see TrustRegion): linearizes at `x`
  // and solves the damped system, raising the damping after each step that
  // would not decrease the error, until a step does; `x` then takes it.
  // After an undamped step, a minimum (kNoDecrease) is first looked for with
  // that step's factor, H where it began, which near a minimum is H here to
  // first order in the step: no factorization. Sets the error at `x` before
  // and after.
  StepOutcome StepWithin(TrustRegion* region, std::vector<Pose>* x,
                         double* chi2_before, double* chi2_after);
  // Levenberg–Marquardt iterations until a step decreases the error by less
  // than `options.relative_decrease` of it, no step can (kNoDecrease), or
  // `options.max_iterations` steps were taken (not converged). The error
  // never increases. With a finite `reach`, it also stops (kOutOfReach, not
  // converged) once the error could not come under `reach` in the steps
  // left even if each lowered it as much as the last one did.
  MinimizeResult Minimize(
      std::vector<Pose>* x, const ConvergenceOptions& options,
      double reach = std::numeric_limits<double>::infinity());
  // Σ w rᵀ Ω r over the problem's edges at `x` (w: their weights).
  double Chi2(const std::vector<Pose>& x) const;

  // At `x`, a minimum of the problem: for each group of edges (indices into
  // edges(); a group's weights all positive, or all 0), to first order how
  // much higher the minimum is with the group than without it: by how much
  // it would fall were a weighted group taken out, or rise were a group of
  // weight 0 put in at weight 1. That is rᵀ (Σ ∓ J H⁻¹ Jᵀ)⁻¹ r, with r the
  // group's residuals at `x`, Σ their covariance (the inverse of their
  // weighted information), J their Jacobians, H the Gauss–Newton matrix at
  // `x` (the minus for a group in it). Exact for a linear problem; one
  // factorization of H and, per group, a sparse solve per residual
  // coordinate. +∞ for a group whose taking out would leave the problem
  // without a unique minimum. If `without` is given, (*without)[f][g] is,
  // for a group f in and a group g of weight 0, g's change at the minimum
  // without f, to first order: r_g + J_g δ in place of r_g, δ = H⁻¹ J_fᵀ
  // (Σ_f − J_f H⁻¹ J_fᵀ)⁻¹ r_f the step that takes f out (exact for a linear
  // problem), H held; one more solve per group f. With `reach` (one per
  // group), only the pairs where δ can bring g's change from over reach[g]
  // to under it (a bound, not a solve, rules out the others) are found: the
  // row of an f with none is empty, and the other pairs of a row are +∞.
  // +∞ for g in; the row of f is empty if f is of weight 0 or its change
  // is +∞. Returns false if H is not positive definite.
  bool ChangesOfMinimum(const std::vector<Pose>& x,
                        const std::vector<std::vector<int>>& groups,
                        std::vector<double>* changes,
                        std::vector<std::vector<double>>* without = nullptr,
                        const std::vector<double>& reach = {});

 private:
  static constexpr int D = Pose::kDof;
  using Block = Eigen::Matrix<double, D, D>;
  struct Slots {
    int from, to;      // blocks, -1 for poses held fixed
    int off_diagonal;  // -1 if either pose is held fixed
  };

  // Builds the normal equations H δ = rhs at `x`: the off-diagonal blocks in
  // system_, the diagonal ones in diagonal_, rhs (minus the gradient) in
  // rhs_, and the damping's scaling S. Returns the error at `x`.
  double Linearize(const std::vector<Pose>& x);
  // Solves (H + damping·S) δ = rhs at the last linearization.
  bool SolveDamped(double damping, Eigen::VectorXd* delta);
  // x ⊞ δ on the free poses.
  void Retract(const Eigen::VectorXd& delta, std::vector<Pose>* x) const;

  std::vector<int> free_;
  std::vector<int> block_of_pose_;  // -1 for poses held fixed
  std::vector<const Edge*> edges_;
  size_t weighed_;               // edges from it on are probes
  std::vector<double> weights_;  // empty: all 1
  std::vector<Slots> slots_;
  std::unique_ptr<BlockCholesky<D>> system_;
  std::vector<Block> diagonal_;
  Eigen::VectorXd rhs_;
  Eigen::VectorXd scaling_;
  // The factor holds H of the last linearization but one: StepWithin's
  // last step was taken undamped.
  bool undamped_factor_ = false;
};

}  // namespace rrr

#endif  // RRR_SOLVER_LOCAL_PROBLEM_H_
