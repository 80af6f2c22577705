#include "rrr/solver/local_problem.h"

#include <stdexcept>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/solver/block_cholesky.h"
#include "rrr/solver/edge_error.h"

namespace rrr {

template <class Pose>
LocalProblem<Pose>::LocalProblem(int num_poses, const std::vector<int>& free,
                                 std::vector<const Edge*> edges)
    : free_(free), block_of_pose_(num_poses, -1), edges_(std::move(edges)) {
  for (size_t b = 0; b < free_.size(); ++b) {
    block_of_pose_[free_[b]] = static_cast<int>(b);
  }
  std::vector<std::pair<int, int>> pattern;
  for (const Edge* e : edges_) {
    const int a = block_of_pose_[e->from], b = block_of_pose_[e->to];
    if (a >= 0 && b >= 0 && a != b) pattern.emplace_back(a, b);
  }
  system_ = std::make_unique<BlockCholesky<D>>(num_free(), pattern);
  slots_.reserve(edges_.size());
  for (const Edge* e : edges_) {
    Slots s{block_of_pose_[e->from], block_of_pose_[e->to], -1};
    if (s.from >= 0 && s.to >= 0 && s.from != s.to) {
      s.off_diagonal = system_->OffDiagonalSlot(s.from, s.to);
    }
    slots_.push_back(s);
  }
}

template <class Pose>
LocalProblem<Pose>::~LocalProblem() = default;

template <class Pose>
void LocalProblem<Pose>::SetWeights(std::vector<double> weights) {
  if (weights.size() != edges_.size()) {
    throw std::invalid_argument("one weight per edge is needed");
  }
  weights_ = std::move(weights);
}

template <class Pose>
bool LocalProblem<Pose>::Step(std::vector<Pose>* x) {
  if (free_.empty()) return true;
  system_->SetZero();
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(num_free() * D);
  for (size_t k = 0; k < edges_.size(); ++k) {
    const Edge& edge = *edges_[k];
    const Slots& s = slots_[k];
    typename Pose::Jacobian ji, jj;
    const typename Pose::Tangent r = EdgeResidualAndJacobians(
        edge.measurement, (*x)[edge.from], (*x)[edge.to], &ji, &jj);
    const double w = weights_.empty() ? 1.0 : weights_[k];
    const typename Pose::Jacobian wi = w * ji.transpose() * edge.information;
    const typename Pose::Jacobian wj = w * jj.transpose() * edge.information;
    if (s.from >= 0) {
      system_->AddDiagonal(s.from, wi * ji);
      rhs.template segment<D>(s.from * D) -= wi * r;
    }
    if (s.to >= 0) {
      system_->AddDiagonal(s.to, wj * jj);
      rhs.template segment<D>(s.to * D) -= wj * r;
    }
    if (s.off_diagonal >= 0) {
      system_->AddOffDiagonal(s.off_diagonal, s.from, s.to, wi * jj);
    }
  }
  Eigen::VectorXd delta;
  if (!system_->Solve(rhs, &delta)) return false;
  for (size_t b = 0; b < free_.size(); ++b) {
    Pose& p = (*x)[free_[b]];
    p = p * Pose::Exp(delta.template segment<D>(b * D));
  }
  return true;
}

template <class Pose>
MinimizeResult LocalProblem<Pose>::Minimize(std::vector<Pose>* x,
                                            const ConvergenceOptions& options) {
  MinimizeResult result;
  result.initial_chi2 = result.final_chi2 = Chi2(*x);
  std::vector<Pose> saved(free_.size());
  while (result.iterations < options.max_iterations) {
    for (size_t b = 0; b < free_.size(); ++b) saved[b] = (*x)[free_[b]];
    if (!Step(x)) {
      result.solved = false;
      return result;
    }
    ++result.iterations;
    const double chi2 = Chi2(*x);
    if (!(chi2 <= result.final_chi2)) {  // diverging: keep the best estimate
      for (size_t b = 0; b < free_.size(); ++b) (*x)[free_[b]] = saved[b];
      result.converged = true;
      return result;
    }
    const double decrease = result.final_chi2 - chi2;
    result.final_chi2 = chi2;
    if (decrease <= options.relative_decrease * chi2) {
      result.converged = true;
      return result;
    }
  }
  return result;
}

template <class Pose>
double LocalProblem<Pose>::Chi2(const std::vector<Pose>& x) const {
  double chi2 = 0.0;
  for (size_t k = 0; k < edges_.size(); ++k) {
    chi2 += (weights_.empty() ? 1.0 : weights_[k]) * EdgeChi2(*edges_[k], x);
  }
  return chi2;
}

template class LocalProblem<Pose2>;
template class LocalProblem<Pose3>;

}  // namespace rrr
