// The error of one relative-pose edge and its Jacobians.
#ifndef RRR_SOLVER_EDGE_ERROR_H_
#define RRR_SOLVER_EDGE_ERROR_H_

#include "rrr/graph/pose_graph.h"

namespace rrr {

// r = Log(z⁻¹ · x_i⁻¹ · x_j), the residual of edge z between x_i and x_j in
// the tangent space.
template <class Pose>
typename Pose::Tangent EdgeResidual(const Pose& z, const Pose& xi,
                                    const Pose& xj) {
  return z.inverse().operator*(xi.between(xj)).Log();
}

// The squared Mahalanobis error rᵀ Ω r of `edge` at the estimates `x`.
template <class Pose>
double EdgeChi2(const Constraint<Pose>& edge, const std::vector<Pose>& x) {
  const typename Pose::Tangent r =
      EdgeResidual(edge.measurement, x[edge.from], x[edge.to]);
  return r.dot(edge.information * r);
}

// The residual and its exact Jacobians with respect to right perturbations
// x_i · Exp(δ_i) and x_j · Exp(δ_j): r(δ) ≈ r + J_i δ_i + J_j δ_j.
template <class Pose>
typename Pose::Tangent EdgeResidualAndJacobians(const Pose& z, const Pose& xi,
                                                const Pose& xj,
                                                typename Pose::Jacobian* ji,
                                                typename Pose::Jacobian* jj) {
  typename Pose::Tangent r = EdgeResidual(z, xi, xj);
  *jj = Pose::RightJacobianInverse(r);
  *ji = -(*jj) * xj.between(xi).Adjoint();
  return r;
}

}  // namespace rrr

#endif  // RRR_SOLVER_EDGE_ERROR_H_
