#include "rrr/solver/local_problem.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/solver/block_cholesky.h"
#include "rrr/solver/edge_error.h"

namespace rrr {

template <class Pose>
LocalProblem<Pose>::LocalProblem(int num_poses, const std::vector<int>& free,
                                 std::vector<const Edge*> edges, size_t weighed)
    : free_(free),
      block_of_pose_(num_poses, -1),
      edges_(std::move(edges)),
      weighed_(std::min(weighed, edges_.size())) {
  for (size_t b = 0; b < free_.size(); ++b) {
    block_of_pose_[free_[b]] = static_cast<int>(b);
  }
  std::vector<std::pair<int, int>> pattern;
  for (size_t k = 0; k < weighed_; ++k) {
    const int a = block_of_pose_[edges_[k]->from];
    const int b = block_of_pose_[edges_[k]->to];
    if (a >= 0 && b >= 0 && a != b) pattern.emplace_back(a, b);
  }
  system_ = std::make_unique<BlockCholesky<D>>(num_free(), pattern);
  slots_.reserve(edges_.size());
  for (size_t k = 0; k < edges_.size(); ++k) {
    const Edge* e = edges_[k];
    Slots s{block_of_pose_[e->from], block_of_pose_[e->to], -1};
    if (k < weighed_ && s.from >= 0 && s.to >= 0 && s.from != s.to) {
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
  for (size_t k = weighed_; k < weights.size(); ++k) {
    if (weights[k] != 0.0) {
      throw std::invalid_argument("a probe's weight must be 0");
    }
  }
  weights_ = std::move(weights);
  undamped_factor_ = false;
}

template <class Pose>
double LocalProblem<Pose>::Linearize(const std::vector<Pose>& x) {
  system_->SetZero();
  diagonal_.assign(free_.size(), Block::Zero());
  rhs_ = Eigen::VectorXd::Zero(num_free() * D);
  double chi2 = 0.0;
  for (size_t k = 0; k < weighed_; ++k) {
    const Edge& edge = *edges_[k];
    const Slots& s = slots_[k];
    typename Pose::Jacobian ji, jj;
    const typename Pose::Tangent r = EdgeResidualAndJacobians(
        edge.measurement, x[edge.from], x[edge.to], &ji, &jj);
    const double w = weights_.empty() ? 1.0 : weights_[k];
    chi2 += w * r.dot(edge.information * r);
    const Block wi = w * ji.transpose() * edge.information;
    const Block wj = w * jj.transpose() * edge.information;
    if (s.from >= 0) {
      diagonal_[s.from] += wi * ji;
      rhs_.template segment<D>(s.from * D) -= wi * r;
    }
    if (s.to >= 0) {
      diagonal_[s.to] += wj * jj;
      rhs_.template segment<D>(s.to * D) -= wj * r;
    }
    if (s.off_diagonal >= 0) {
      system_->AddOffDiagonal(s.off_diagonal, s.from, s.to, wi * jj);
    }
  }
  // The damping's scaling: diag(H), floored where no edge constrains a
  // coordinate.
  double largest = 0.0;
  for (const Block& block : diagonal_) {
    largest = std::max(largest, block.diagonal().maxCoeff());
  }
  scaling_.resize(num_free() * D);
  for (size_t b = 0; b < free_.size(); ++b) {
    scaling_.template segment<D>(b * D) =
        diagonal_[b].diagonal().cwiseMax(1e-12 * largest);
  }
  return chi2;
}

template <class Pose>
bool LocalProblem<Pose>::SolveDamped(double damping, Eigen::VectorXd* delta) {
  for (size_t b = 0; b < free_.size(); ++b) {
    Block damped = diagonal_[b];
    damped.diagonal() += damping * scaling_.template segment<D>(b * D);
    system_->SetDiagonal(static_cast<int>(b), damped);
  }
  return system_->Solve(rhs_, delta);
}

template <class Pose>
void LocalProblem<Pose>::Retract(const Eigen::VectorXd& delta,
                                 std::vector<Pose>* x) const {
  for (size_t b = 0; b < free_.size(); ++b) {
    Pose& p = (*x)[free_[b]];
    p = p * Pose::Exp(delta.template segment<D>(b * D));
  }
}

template <class Pose>
bool LocalProblem<Pose>::Step(std::vector<Pose>* x) {
  if (free_.empty()) return true;
  undamped_factor_ = false;
  Linearize(*x);
  Eigen::VectorXd delta;
  if (!SolveDamped(0.0, &delta)) return false;
  Retract(delta, x);
  return true;
}

template <class Pose>
StepOutcome LocalProblem<Pose>::StepWithin(TrustRegion* region,
                                           std::vector<Pose>* x,
                                           double* chi2_before,
                                           double* chi2_after) {
  // Each failure multiplies the damping by a growth that doubles: after
  // kMaxTries it has grown by 2^(kMaxTries·(kMaxTries+1)/2) from where it
  // started, far beyond any useful step.
  constexpr int kMaxTries = 12;
  *chi2_before = *chi2_after = free_.empty() ? Chi2(*x) : Linearize(*x);
  region->stationary = true;
  if (free_.empty()) return StepOutcome::kNoDecrease;
  const double chi2 = *chi2_before;
  Eigen::VectorXd delta;
  // After an undamped step the factor still holds H where that step began.
  // Near a minimum H barely changes over a step, so the decrease it
  // predicts here tells a minimum without factorizing again.
  if (undamped_factor_) {
    undamped_factor_ = false;
    if (system_->SolveFactorized(rhs_, &delta) &&
        !(delta.dot(rhs_) > region->relative_decrease * chi2)) {
      return StepOutcome::kNoDecrease;
    }
  }
  const auto raise = [region] {
    region->damping = region->damping > 0.0 ? region->damping * region->growth
                                            : TrustRegion::kFirstDamping;
    region->growth *= 2.0;
  };
  std::vector<Pose> saved(free_.size());
  bool solved_any = false;
  for (int tries = 0; tries < kMaxTries; ++tries) {
    const double damping = region->damping;
    if (!SolveDamped(damping, &delta)) {
      raise();
      continue;
    }
    solved_any = true;
    // The decrease the linear model predicts for δ: with
    // (H + λS) δ = rhs it is 2 rhsᵀδ − δᵀHδ = rhsᵀδ + λ δᵀSδ.
    const double predicted =
        delta.dot(rhs_) + damping * delta.dot(scaling_.cwiseProduct(delta));
    if (!(predicted > region->relative_decrease * chi2)) {
      return StepOutcome::kNoDecrease;
    }
    for (size_t b = 0; b < free_.size(); ++b) saved[b] = (*x)[free_[b]];
    Retract(delta, x);
    const double after = Chi2(*x);
    const double gain = (chi2 - after) / predicted;
    if (gain > 1e-3) {  // Ceres's least acceptable gain ratio
      *chi2_after = after;
      if (damping > 0.0) {  // Nielsen's update
        const double c = 2.0 * gain - 1.0;
        region->damping *= std::max(1.0 / 3.0, 1.0 - c * c * c);
        if (region->damping < TrustRegion::kLeastDamping) {
          region->damping = 0.0;
        }
      }
      region->growth = 2.0;
      undamped_factor_ = damping == 0.0;
      return StepOutcome::kTaken;
    }
    for (size_t b = 0; b < free_.size(); ++b) (*x)[free_[b]] = saved[b];
    raise();
  }
  region->stationary = false;
  return solved_any ? StepOutcome::kNoDecrease : StepOutcome::kNotSolved;
}

template <class Pose>
MinimizeResult LocalProblem<Pose>::Minimize(std::vector<Pose>* x,
                                            const ConvergenceOptions& options,
                                            double reach) {
  MinimizeResult result;
  if (options.max_iterations <= 0) {
    result.initial_chi2 = result.final_chi2 = Chi2(*x);
  }
  TrustRegion region;
  region.relative_decrease = options.relative_decrease;
  while (result.iterations < options.max_iterations) {
    double before = 0.0, chi2 = 0.0;
    const StepOutcome outcome = StepWithin(&region, x, &before, &chi2);
    if (result.iterations == 0)
      result.initial_chi2 = result.final_chi2 = before;
    if (outcome == StepOutcome::kNotSolved) {
      result.solved = false;
      result.stop = StopReason::kNotSolved;
      return result;
    }
    if (outcome == StepOutcome::kNoDecrease) {
      result.converged = true;
      result.stop = region.stationary ? StopReason::kStationary
                                      : StopReason::kNoAcceptableStep;
      return result;
    }
    ++result.iterations;
    const double decrease = result.final_chi2 - chi2;
    result.final_chi2 = chi2;
    if (decrease <= options.relative_decrease * chi2) {
      result.converged = true;
      result.stop = StopReason::kRelativeDecrease;
      return result;
    }
    if (chi2 - (options.max_iterations - result.iterations) * decrease >
        reach) {
      result.stop = StopReason::kOutOfReach;
      return result;
    }
  }
  if (options.max_iterations > 0) result.stop = StopReason::kIterationLimit;
  return result;
}

const char* ToString(StopReason reason) {
  switch (reason) {
    case StopReason::kNotRun:
      return "not_run";
    case StopReason::kRelativeDecrease:
      return "relative_decrease";
    case StopReason::kStationary:
      return "stationary";
    case StopReason::kNoAcceptableStep:
      return "no_acceptable_step";
    case StopReason::kIterationLimit:
      return "iteration_limit";
    case StopReason::kOutOfReach:
      return "out_of_reach";
    case StopReason::kNotSolved:
      return "not_solved";
  }
  return "unknown";
}

template <class Pose>
double LocalProblem<Pose>::Chi2(const std::vector<Pose>& x) const {
  double chi2 = 0.0;
  for (size_t k = 0; k < weighed_; ++k) {
    chi2 += (weights_.empty() ? 1.0 : weights_[k]) * EdgeChi2(*edges_[k], x);
  }
  return chi2;
}

template <class Pose>
bool LocalProblem<Pose>::ChangesOfMinimum(
    const std::vector<Pose>& x, const std::vector<std::vector<int>>& groups,
    std::vector<double>* changes, std::vector<std::vector<double>>* without,
    const std::vector<double>& reach) {
  undamped_factor_ = false;
  Linearize(x);
  // Each group's residuals r, Jᵀ by the blocks it touches, Σ ∓ J H⁻¹ Jᵀ and,
  // for a group in, y = (Σ − J H⁻¹ Jᵀ)⁻¹ r and the energy δᵀ H δ = yᵀ J H⁻¹
  // Jᵀ y of the step δ = H⁻¹ Jᵀ y that takes it out.
  struct Terms {
    Eigen::VectorXd r;
    std::vector<int> blocks;
    Eigen::MatrixXd jt;
    Eigen::LDLT<Eigen::MatrixXd> s;
    bool in = false;
    Eigen::VectorXd y;
    double energy = 0.0;
  };
  std::vector<Terms> terms;
  for (size_t b = 0; b < free_.size(); ++b) {
    system_->SetDiagonal(static_cast<int>(b), diagonal_[b]);
  }
  if (!system_->Factorize()) return false;
  changes->clear();
  for (const std::vector<int>& group : groups) {
    const int m = static_cast<int>(group.size()) * D;
    Eigen::VectorXd r(m);
    Eigen::MatrixXd covariance = Eigen::MatrixXd::Zero(m, m);
    // Jᵀ by the free poses the group touches.
    std::vector<int> blocks;
    Eigen::MatrixXd jt = Eigen::MatrixXd::Zero(2 * Eigen::Index{m}, m);
    const auto add = [&](int pose, const Block& j, int column) {
      const int block = block_of_pose_[pose];
      if (block < 0) return;
      const auto at = std::find(blocks.begin(), blocks.end(), block);
      const int i = static_cast<int>(at - blocks.begin());
      if (at == blocks.end()) blocks.push_back(block);
      jt.block<D, D>(i * D, column) += j.transpose();
    };
    bool in = false;
    for (size_t l = 0; l < group.size(); ++l) {
      const Edge& edge = *edges_[group[l]];
      const size_t k = group[l];
      const double w = k >= weighed_      ? 0.0
                       : weights_.empty() ? 1.0
                                          : weights_[k];
      in = w > 0.0;
      typename Pose::Jacobian ji, jj;
      r.template segment<D>(l * D) = EdgeResidualAndJacobians(
          edge.measurement, x[edge.from], x[edge.to], &ji, &jj);
      covariance.block<D, D>(l * D, l * D) =
          (in ? w * edge.information : edge.information).inverse();
      add(edge.from, ji, static_cast<int>(l) * D);
      add(edge.to, jj, static_cast<int>(l) * D);
    }
    const Eigen::MatrixXd form = system_->InverseForm(
        blocks, jt.topRows(static_cast<int>(blocks.size()) * D));
    const Eigen::LDLT<Eigen::MatrixXd> s(
        in ? Eigen::MatrixXd(covariance - form)
           : Eigen::MatrixXd(covariance + form));
    const double change = r.dot(s.solve(r));
    changes->push_back(s.isPositive() && std::isfinite(change)
                           ? change
                           : std::numeric_limits<double>::infinity());
    if (without) {
      Terms t;
      t.r = r;
      t.blocks = blocks;
      t.jt = jt.topRows(static_cast<int>(blocks.size()) * D);
      t.s = s;
      t.in = in;
      if (in && s.isPositive()) {
        t.y = s.solve(r);
        t.energy = t.y.dot(form * t.y);
      }
      terms.push_back(std::move(t));
    }
  }
  if (!without) return true;
  // Whether taking f out can bring g from over reach[g] to under it: the
  // step lowers √(g's change) by at most √(its energy), as J_gᵀ (Σ_g + J_g
  // H⁻¹ J_gᵀ)⁻¹ J_g ≤ H.
  const auto reaches = [&](const Terms& out, size_t g) {
    if (reach.empty()) return true;
    if (!((*changes)[g] > reach[g])) return false;
    const double gap = std::sqrt((*changes)[g]) - std::sqrt(reach[g]);
    return out.energy >= gap * gap;
  };
  without->assign(groups.size(), {});
  for (size_t f = 0; f < terms.size(); ++f) {
    const Terms& out = terms[f];
    if (!out.in || !out.s.isPositive()) continue;
    bool any = false;
    for (size_t g = 0; g < terms.size() && !any; ++g) {
      any = !terms[g].in && reaches(out, g);
    }
    if (!any) continue;
    // The minimum moves by δ = H⁻¹ Jᵀ y when f is taken out.
    const Eigen::VectorXd& y = out.y;
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(Eigen::Index{num_free()} * D);
    for (size_t i = 0; i < out.blocks.size(); ++i) {
      rhs.template segment<D>(out.blocks[i] * D) +=
          out.jt.middleRows(static_cast<int>(i) * D, D) * y;
    }
    Eigen::VectorXd delta;
    if (!system_->SolveFactorized(rhs, &delta)) continue;
    (*without)[f].assign(groups.size(),
                         std::numeric_limits<double>::infinity());
    for (size_t g = 0; g < terms.size(); ++g) {
      const Terms& put = terms[g];
      if (put.in || !reaches(out, g)) continue;
      Eigen::VectorXd moved = put.r;
      for (size_t i = 0; i < put.blocks.size(); ++i) {
        moved += put.jt.middleRows(static_cast<int>(i) * D, D).transpose() *
                 delta.template segment<D>(put.blocks[i] * D);
      }
      (*without)[f][g] = moved.dot(put.s.solve(moved));
    }
  }
  return true;
}

template class LocalProblem<Pose2>;
template class LocalProblem<Pose3>;

}  // namespace rrr
