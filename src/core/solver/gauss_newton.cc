#include "rrr/solver/gauss_newton.h"

#include <cmath>
#include <limits>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/solver/edge_error.h"

namespace rrr {

template <class Pose>
GaussNewton<Pose>::GaussNewton(const PoseGraph<Pose>& graph, int iterations)
    : graph_(graph),
      iterations_(iterations),
      initial_(graph.ComposeOdometry()),
      block_of_pose_(graph.num_poses(), 0) {
  block_of_pose_[0] = -1;
  for (const int k : graph.fixed()) block_of_pose_[k] = -1;
  int blocks = 0;
  for (int& b : block_of_pose_) b = (b < 0) ? -1 : blocks++;

  std::vector<std::pair<int, int>> pattern;
  for (const auto* edges : {&graph.odometry(), &graph.loops()}) {
    for (const auto& e : *edges) {
      const int a = block_of_pose_[e.from], b = block_of_pose_[e.to];
      if (a >= 0 && b >= 0) pattern.emplace_back(a, b);
    }
  }
  system_ = std::make_unique<BlockCholesky<Pose::kDof>>(blocks, pattern);
  for (const auto& e : graph.odometry()) odometry_slots_.push_back(SlotsOf(e));
  for (const auto& e : graph.loops()) loop_slots_.push_back(SlotsOf(e));
}

template <class Pose>
GaussNewton<Pose>::~GaussNewton() = default;

template <class Pose>
typename GaussNewton<Pose>::EdgeSlots GaussNewton<Pose>::SlotsOf(
    const Constraint<Pose>& edge) const {
  EdgeSlots s{block_of_pose_[edge.from], block_of_pose_[edge.to], -1};
  if (s.block_from >= 0 && s.block_to >= 0) {
    s.off_diagonal = system_->OffDiagonalSlot(s.block_from, s.block_to);
  }
  return s;
}

template <class Pose>
void GaussNewton<Pose>::Accumulate(const Constraint<Pose>& edge,
                                   const EdgeSlots& slots,
                                   const std::vector<Pose>& x,
                                   Eigen::VectorXd* rhs) {
  constexpr int D = Pose::kDof;
  typename Pose::Jacobian ji, jj;
  const typename Pose::Tangent r = EdgeResidualAndJacobians(
      edge.measurement, x[edge.from], x[edge.to], &ji, &jj);
  const typename Pose::Jacobian wi = ji.transpose() * edge.information;
  const typename Pose::Jacobian wj = jj.transpose() * edge.information;
  if (slots.block_from >= 0) {
    system_->AddDiagonal(slots.block_from, wi * ji);
    rhs->template segment<D>(slots.block_from * D) -= wi * r;
  }
  if (slots.block_to >= 0) {
    system_->AddDiagonal(slots.block_to, wj * jj);
    rhs->template segment<D>(slots.block_to * D) -= wj * r;
  }
  if (slots.off_diagonal >= 0) {
    system_->AddOffDiagonal(slots.off_diagonal, slots.block_from,
                            slots.block_to, wi * jj);
  }
}

template <class Pose>
bool GaussNewton<Pose>::Step(const std::vector<int>& active_loops,
                             std::vector<Pose>* x) {
  constexpr int D = Pose::kDof;
  system_->SetZero();
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(system_->num_blocks() * D);
  const auto& odometry = graph_.odometry();
  for (size_t k = 0; k < odometry.size(); ++k) {
    Accumulate(odometry[k], odometry_slots_[k], *x, &rhs);
  }
  for (const int k : active_loops) {
    Accumulate(graph_.loops()[k], loop_slots_[k], *x, &rhs);
  }
  Eigen::VectorXd delta;
  if (!system_->Solve(rhs, &delta)) return false;
  for (int p = 0; p < graph_.num_poses(); ++p) {
    const int b = block_of_pose_[p];
    if (b >= 0) {
      (*x)[p] = (*x)[p] * Pose::Exp(delta.template segment<D>(b * D));
    }
  }
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
  std::vector<Pose> x = initial_;
  for (int it = 0; it < iterations_; ++it) {
    if (!Step(active_loops, &x)) {
      SubsetErrors failed;
      failed.solved = false;
      failed.num_edges =
          static_cast<int>(graph_.odometry().size() + active_loops.size());
      failed.total_chi2 = std::numeric_limits<double>::infinity();
      failed.loop_chi2.assign(active_loops.size(), failed.total_chi2);
      return failed;
    }
  }
  return Evaluate(active_loops, x);
}

template <class Pose>
std::vector<Pose> GaussNewton<Pose>::Optimize(
    const std::vector<int>& active_loops, const ConvergenceOptions& options,
    int* iterations_run) {
  std::vector<Pose> x = initial_;
  double chi2 = Evaluate(active_loops, x).total_chi2;
  int it = 0;
  while (it < options.max_iterations) {
    std::vector<Pose> next = x;
    if (!Step(active_loops, &next)) break;
    ++it;
    const double next_chi2 = Evaluate(active_loops, next).total_chi2;
    if (!(next_chi2 <= chi2)) break;  // diverging: keep the best estimate
    x.swap(next);
    const double decrease = chi2 - next_chi2;
    chi2 = next_chi2;
    if (decrease <= options.relative_decrease * chi2) break;
  }
  if (iterations_run) *iterations_run = it;
  return x;
}

template class GaussNewton<Pose2>;
template class GaussNewton<Pose3>;

}  // namespace rrr
