// One odometry chain's map placed in another's frame by the loops between
// them, both maps held rigid.
#ifndef RRR_CORE_RRR_CHAINS_RIGID_FIT_H_
#define RRR_CORE_RRR_CHAINS_RIGID_FIT_H_

#include <vector>

#include "rrr/graph/pose_graph.h"
#include "rrr/solver/convergence.h"
#include "rrr/solver/edge_error.h"

namespace rrr {

// In a graph of two chains, the first's poses before `first_of_b` and the
// second's from it on: the frame in which the second's poses of `x` must be
// put for the loop `e` between the chains to hold exactly.
template <class Pose>
Pose FrameBy(const Constraint<Pose>& e, int first_of_b,
             const std::vector<Pose>& x) {
  const bool from_first = e.from < first_of_b;
  const int a = from_first ? e.from : e.to;
  const int b = from_first ? e.to : e.from;
  const Pose z = from_first ? e.measurement : e.measurement.inverse();
  return x[a] * z * x[b].inverse();
}

// `x` with the second chain's poses moved into FrameBy(e, first_of_b, x).
template <class Pose>
std::vector<Pose> PlacedBy(const Constraint<Pose>& e, int first_of_b,
                           std::vector<Pose> x) {
  const Pose frame = FrameBy(e, first_of_b, x);
  for (size_t p = first_of_b; p < x.size(); ++p) x[p] = frame * x[p];
  return x;
}

// The least error of the loops `loops` of `graph` between its two chains
// (as FrameBy) with both chains' estimates held as they are and only the
// second's frame free; sets `*frame` to that frame (Gauss–Newton from
// FrameBy of the first loop, while the error decreases).
template <class Pose>
double RigidFit(const PoseGraph<Pose>& graph, const std::vector<int>& loops,
                int first_of_b, Pose* frame) {
  const std::vector<Pose>& x = graph.estimates();
  const auto moved = [&](int p, const Pose& m) {
    return p < first_of_b ? x[p] : m * x[p];
  };
  const auto error = [&](const Pose& m) {
    double sum = 0.0;
    for (const int k : loops) {
      const Constraint<Pose>& e = graph.loops()[k];
      const typename Pose::Tangent r =
          EdgeResidual(e.measurement, moved(e.from, m), moved(e.to, m));
      sum += r.dot(e.information * r);
    }
    return sum;
  };
  Pose m = FrameBy(graph.loops()[loops.front()], first_of_b, x);
  double chi2 = error(m);
  const ConvergenceOptions convergence;
  for (int it = 0; it < convergence.max_iterations; ++it) {
    typename Pose::Jacobian h = Pose::Jacobian::Zero();
    typename Pose::Tangent g = Pose::Tangent::Zero();
    for (const int k : loops) {
      const Constraint<Pose>& e = graph.loops()[k];
      typename Pose::Jacobian ji, jj;
      const typename Pose::Tangent r = EdgeResidualAndJacobians(
          e.measurement, moved(e.from, m), moved(e.to, m), &ji, &jj);
      // The second chain's pose b moves as m·Exp(δ)·b = m·b·Exp(Ad(b⁻¹)δ).
      const bool second_is_to = e.from < first_of_b;
      const Pose& b = x[second_is_to ? e.to : e.from];
      const typename Pose::Jacobian j =
          (second_is_to ? jj : ji) * b.inverse().Adjoint();
      h += j.transpose() * e.information * j;
      g += j.transpose() * e.information * r;
    }
    const Pose next = m * Pose::Exp(-h.ldlt().solve(g));
    const double next_chi2 = error(next);
    if (!(next_chi2 < chi2)) break;
    const bool small = chi2 - next_chi2 < convergence.relative_decrease * chi2;
    m = next;
    chi2 = next_chi2;
    if (small) break;
  }
  *frame = m;
  return chi2;
}

}  // namespace rrr

#endif  // RRR_CORE_RRR_CHAINS_RIGID_FIT_H_
