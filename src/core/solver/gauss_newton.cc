#include "rrr/solver/gauss_newton.h"

#include <algorithm>
#include <limits>
#include <memory>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/solver/block_cholesky.h"
#include "rrr/solver/edge_error.h"

namespace rrr {

// The linear system of one solve: the stretch of chain poses first..last
// with `first` held fixed, the odometry edges among them and the active loops.
template <class Pose>
class GaussNewton<Pose>::Problem {
 public:
  static constexpr int D = Pose::kDof;

  Problem(const PoseGraph<Pose>& graph, const std::vector<int>& active_loops,
          int first, int last)
      : first_(first), block_of_pose_(last - first + 1, 0) {
    block_of_pose_[0] = -1;
    for (const int k : graph.fixed()) {
      if (k >= first && k <= last) block_of_pose_[k - first] = -1;
    }
    int blocks = 0;
    for (int& b : block_of_pose_) b = (b < 0) ? -1 : blocks++;
    for (const auto& e : graph.odometry()) {
      if (std::min(e.from, e.to) >= first && std::max(e.from, e.to) <= last) {
        edges_.push_back(&e);
      }
    }
    for (const int k : active_loops) edges_.push_back(&graph.loops()[k]);
    std::vector<std::pair<int, int>> pattern;
    for (const auto* e : edges_) {
      const int a = BlockOf(e->from), b = BlockOf(e->to);
      if (a >= 0 && b >= 0) pattern.emplace_back(a, b);
    }
    system_ = std::make_unique<BlockCholesky<D>>(blocks, pattern);
    for (const auto* e : edges_) {
      Slots s{BlockOf(e->from), BlockOf(e->to), -1};
      if (s.from >= 0 && s.to >= 0) {
        s.off_diagonal = system_->OffDiagonalSlot(s.from, s.to);
      }
      slots_.push_back(s);
    }
    rhs_.resize(static_cast<Eigen::Index>(blocks) * D);
  }

  int num_edges() const { return static_cast<int>(edges_.size()); }

  // One Gauss–Newton step on `x`; false if the system is not solvable.
  bool Step(std::vector<Pose>* x) {
    system_->SetZero();
    rhs_.setZero();
    for (size_t k = 0; k < edges_.size(); ++k)
      Accumulate(*edges_[k], slots_[k], *x);
    if (!system_->Solve(rhs_, &delta_)) return false;
    for (size_t p = 0; p < block_of_pose_.size(); ++p) {
      const int b = block_of_pose_[p];
      if (b >= 0) {
        (*x)[first_ + p] =
            (*x)[first_ + p] * Pose::Exp(delta_.template segment<D>(b * D));
      }
    }
    return true;
  }

 private:
  int BlockOf(int pose) const { return block_of_pose_[pose - first_]; }

  struct Slots {
    int from, to;      // blocks, -1 for fixed poses
    int off_diagonal;  // -1 if either pose is fixed
  };

  void Accumulate(const Constraint<Pose>& edge, const Slots& slots,
                  const std::vector<Pose>& x) {
    typename Pose::Jacobian ji, jj;
    const typename Pose::Tangent r = EdgeResidualAndJacobians(
        edge.measurement, x[edge.from], x[edge.to], &ji, &jj);
    const typename Pose::Jacobian wi = ji.transpose() * edge.information;
    const typename Pose::Jacobian wj = jj.transpose() * edge.information;
    if (slots.from >= 0) {
      system_->AddDiagonal(slots.from, wi * ji);
      rhs_.template segment<D>(slots.from * D) -= wi * r;
    }
    if (slots.to >= 0) {
      system_->AddDiagonal(slots.to, wj * jj);
      rhs_.template segment<D>(slots.to * D) -= wj * r;
    }
    if (slots.off_diagonal >= 0) {
      system_->AddOffDiagonal(slots.off_diagonal, slots.from, slots.to,
                              wi * jj);
    }
  }

  int first_;
  std::vector<int> block_of_pose_;  // of poses first..last
  std::vector<const Constraint<Pose>*> edges_;
  std::vector<Slots> slots_;
  std::unique_ptr<BlockCholesky<D>> system_;
  Eigen::VectorXd rhs_, delta_;
};

template <class Pose>
GaussNewton<Pose>::GaussNewton(const PoseGraph<Pose>& graph, int iterations)
    : graph_(graph),
      iterations_(iterations),
      initial_(graph.ComposeOdometry()) {
  for (const int k : graph.fixed()) last_fixed_ = std::max(last_fixed_, k);
}

template <class Pose>
bool GaussNewton<Pose>::Run(const std::vector<int>& active_loops,
                            int max_iterations,
                            const ConvergenceOptions* options,
                            std::vector<Pose>* x, int* iterations_run,
                            int* spanned_edges) const {
  *x = initial_;
  if (iterations_run) *iterations_run = 0;
  if (spanned_edges) *spanned_edges = 0;
  // The stretch of chain that the active loops (and fixed poses) span. The
  // chain after it hangs free and follows odometry with zero error. The
  // chain before it is a rigid path from the fixed first pose: relative-pose
  // errors do not change under a rigid motion of the rest, so every
  // Gauss–Newton step leaves that path at odometry with zero error, exactly
  // as if its last pose were fixed.
  int first = last_fixed_ > 0 ? 0 : graph_.num_poses() - 1;
  int last = last_fixed_;
  for (const int k : active_loops) {
    const auto& loop = graph_.loops()[k];
    first = std::min({first, loop.from, loop.to});
    last = std::max({last, loop.from, loop.to});
  }
  if (last <= first) return true;
  Problem problem(graph_, active_loops, first, last);
  if (spanned_edges) *spanned_edges = problem.num_edges();
  // Carries the free end of the chain along with its last constrained pose.
  const auto carry_tail = [&](std::vector<Pose>* y) {
    for (int p = last + 1; p < graph_.num_poses(); ++p) {
      (*y)[p] = (*y)[last] * initial_[last].between(initial_[p]);
    }
  };
  double chi2 = options ? Evaluate(active_loops, *x).total_chi2 : 0.0;
  std::vector<Pose> next;
  for (int it = 0; it < max_iterations; ++it) {
    if (!options) {  // a fixed number of steps, in place
      if (!problem.Step(x)) return false;
      if (iterations_run) ++*iterations_run;
      continue;
    }
    next = *x;
    if (!problem.Step(&next)) return false;
    if (iterations_run) ++*iterations_run;
    carry_tail(&next);
    const double next_chi2 = Evaluate(active_loops, next).total_chi2;
    if (!(next_chi2 <= chi2)) break;  // diverging: keep the best estimate
    const double decrease = chi2 - next_chi2;
    chi2 = next_chi2;
    x->swap(next);
    if (decrease <= options->relative_decrease * chi2) break;
  }
  carry_tail(x);
  return true;
}

template <class Pose>
SubsetErrors GaussNewton<Pose>::Evaluate(const std::vector<int>& active_loops,
                                         const std::vector<Pose>& x) const {
  SubsetErrors out;
  for (const auto& e : graph_.odometry()) out.total_chi2 += EdgeChi2(e, x);
  out.loop_chi2.reserve(active_loops.size());
  for (const int k : active_loops) {
    out.loop_chi2.push_back(EdgeChi2(graph_.loops()[k], x));
    out.total_chi2 += out.loop_chi2.back();
  }
  out.num_edges =
      static_cast<int>(graph_.odometry().size() + active_loops.size());
  return out;
}

template <class Pose>
SubsetErrors GaussNewton<Pose>::Solve(const std::vector<int>& active_loops) {
  std::vector<Pose> x;
  int spanned_edges = 0;
  if (!Run(active_loops, iterations_, nullptr, &x, nullptr, &spanned_edges)) {
    SubsetErrors failed;
    failed.solved = false;
    failed.num_edges =
        static_cast<int>(graph_.odometry().size() + active_loops.size());
    failed.total_chi2 = std::numeric_limits<double>::infinity();
    failed.loop_chi2.assign(active_loops.size(), failed.total_chi2);
    failed.num_spanned_edges = spanned_edges;
    return failed;
  }
  SubsetErrors errors = Evaluate(active_loops, x);
  errors.num_spanned_edges = spanned_edges;
  return errors;
}

template <class Pose>
std::vector<Pose> GaussNewton<Pose>::Optimize(
    const std::vector<int>& active_loops, const ConvergenceOptions& options,
    int* iterations_run) const {
  std::vector<Pose> x;
  Run(active_loops, options.max_iterations, &options, &x, iterations_run);
  return x;
}

template class GaussNewton<Pose2>;
template class GaussNewton<Pose3>;

}  // namespace rrr
