#include "rrr/graph/odometry_chain.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <stdexcept>
#include <string>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"

namespace rrr {
namespace {

template <class M>
M Inverse(const M& spd) {
  return spd.ldlt().solve(M::Identity());
}

}  // namespace

template <class Pose>
OdometryChain<Pose>::OdometryChain()
    : composed_{Pose()}, world_sum_{Covariance::Zero()}, travelled_{0.0} {}

template <class Pose>
void OdometryChain<Pose>::Append(const Pose& z,
                                 const Information& information) {
  const Covariance cov = Inverse(information);
  const Pose next = composed_.back() * z;
  const typename Pose::Jacobian ad = next.Adjoint();
  world_sum_.push_back(world_sum_.back() + ad * cov * ad.transpose());
  composed_.push_back(next);
  steps_.push_back(z);
  step_cov_.push_back(cov);
  travelled_.push_back(travelled_.back() + z.translation().norm());
}

template <class Pose>
void OdometryChain<Pose>::Reserve(int poses) {
  composed_.reserve(poses);
  steps_.reserve(poses);
  step_cov_.reserve(poses);
  world_sum_.reserve(poses);
  travelled_.reserve(poses);
}

template <class Pose>
typename OdometryChain<Pose>::Covariance OdometryChain<Pose>::CovarianceBetween(
    int i, int j) const {
  if (j - i <= kDirectSteps) {
    // Σ_{i,k+1} = Ad(z_k⁻¹) Σ_{i,k} Ad(z_k⁻¹)ᵀ + Σ_k.
    Covariance cov = Covariance::Zero();
    for (int k = i; k < j; ++k) {
      const typename Pose::Jacobian ad = steps_[k].inverse().Adjoint();
      cov = ad * cov * ad.transpose() + step_cov_[k];
    }
    return cov;
  }
  const typename Pose::Jacobian ad = composed_[j].inverse().Adjoint();
  const Covariance cov = ad * (world_sum_[j] - world_sum_[i]) * ad.transpose();
  return 0.5 * (cov + cov.transpose());
}

template <class Pose>
Constraint<Pose> OdometryChain<Pose>::Between(int i, int j) const {
  Constraint<Pose> edge;
  edge.from = i;
  edge.to = j;
  edge.measurement = Relative(i, j);
  edge.information = Inverse(CovarianceBetween(i, j));
  edge.information = 0.5 * (edge.information + edge.information.transpose());
  return edge;
}

template <class Pose>
std::vector<Constraint<Pose>> OdometryStepsOf(const PoseGraph<Pose>& graph) {
  using Information = typename Constraint<Pose>::Information;
  const int n = graph.num_poses();
  std::vector<Constraint<Pose>> steps(std::max(n - 1, 0));
  for (Constraint<Pose>& s : steps) s.from = -1;
  for (const auto& e : graph.odometry()) {
    const bool forward = e.to == e.from + 1;
    const int k = (forward ? e.to : e.from) - 1;  // the step to the later pose
    // The step from k to k+1, seen forwards: z' = z⁻¹ and
    // Ω' = Ad(z)⁻ᵀ Ω Ad(z)⁻¹ for an edge stored backwards.
    Pose step = e.measurement;
    Information omega = e.information;
    if (!forward) {
      const typename Pose::Jacobian ad_inv = e.measurement.Adjoint().inverse();
      step = e.measurement.inverse();
      omega = ad_inv.transpose() * e.information * ad_inv;
    }
    Constraint<Pose>& s = steps[k];
    if (s.from < 0) {
      s.from = k;
      s.to = k + 1;
      s.measurement = step;
      s.information = omega;
      continue;
    }
    // Fuse: the information-weighted mean in the tangent space at z.
    const Information sum = s.information + omega;
    const typename Pose::Tangent shift =
        sum.ldlt().solve(omega * s.measurement.between(step).Log());
    s.measurement = s.measurement * Pose::Exp(shift);
    s.information = sum;
  }
  return steps;
}

template <class Pose>
OdometryChain<Pose> ChainOf(const PoseGraph<Pose>& graph) {
  OdometryChain<Pose> chain;
  chain.Reserve(graph.num_poses());
  for (const Constraint<Pose>& step : OdometryStepsOf(graph)) {
    if (step.from < 0) {
      throw std::invalid_argument(
          "pose " + std::to_string(graph.ids()[chain.num_poses()]) +
          " has no odometry to its predecessor");
    }
    chain.Append(step.measurement, step.information);
  }
  return chain;
}

template class OdometryChain<Pose2>;
template class OdometryChain<Pose3>;
template std::vector<Constraint<Pose2>> OdometryStepsOf(
    const PoseGraph<Pose2>&);
template std::vector<Constraint<Pose3>> OdometryStepsOf(
    const PoseGraph<Pose3>&);
template OdometryChain<Pose2> ChainOf(const PoseGraph<Pose2>&);
template OdometryChain<Pose3> ChainOf(const PoseGraph<Pose3>&);

}  // namespace rrr
