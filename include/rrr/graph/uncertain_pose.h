// A relative pose with its first-order uncertainty, composed along cycles of
// measurements (PCM's consistency test, bounds of what a loop brings).
#ifndef RRR_GRAPH_UNCERTAIN_POSE_H_
#define RRR_GRAPH_UNCERTAIN_POSE_H_

#include <Eigen/Cholesky>

#include "rrr/graph/odometry_chain.h"
#include "rrr/graph/pose_graph.h"

namespace rrr {

// A relative pose with the covariance of its right perturbation:
// pose · Exp(ε), ε ~ N(0, cov).
template <class Pose>
struct UncertainPose {
  using Covariance = typename Constraint<Pose>::Information;
  Pose pose;
  Covariance cov = Covariance::Zero();

  UncertainPose Inverse() const {
    const typename Pose::Jacobian ad = pose.Adjoint();
    return {pose.inverse(), ad * cov * ad.transpose()};
  }
  // this · other: x·Exp(ε₁)·y·Exp(ε₂) = xy·Exp(Ad(y⁻¹)ε₁ + ε₂).
  UncertainPose operator*(const UncertainPose& other) const {
    const typename Pose::Jacobian ad = other.pose.inverse().Adjoint();
    return {pose * other.pose, ad * cov * ad.transpose() + other.cov};
  }
  // The squared Mahalanobis distance of the pose from the identity: for a
  // cycle of measurements, its χ² (e dof) if they agree.
  double SquaredDistance() const {
    const typename Pose::Tangent r = pose.Log();
    return r.dot(cov.ldlt().solve(r));
  }
};

// A loop's measurement, its covariance the inverse of its information.
template <class Pose>
UncertainPose<Pose> MeasurementOf(const Constraint<Pose>& e) {
  using Covariance = typename UncertainPose<Pose>::Covariance;
  return {e.measurement, e.information.ldlt().solve(Covariance::Identity())};
}

// The condensed odometry of `chain` from its pose p to its pose q (either
// order; the identity, certain, if p == q).
template <class Pose>
UncertainPose<Pose> OdometryBetween(const OdometryChain<Pose>& chain, int p,
                                    int q) {
  if (p == q) return {};
  if (p < q) return {chain.Relative(p, q), chain.CovarianceBetween(p, q)};
  return OdometryBetween(chain, q, p).Inverse();
}

}  // namespace rrr

#endif  // RRR_GRAPH_UNCERTAIN_POSE_H_
