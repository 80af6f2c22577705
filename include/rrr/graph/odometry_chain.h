// The odometry chain condensed: one edge between any two of its poses.
#ifndef RRR_GRAPH_ODOMETRY_CHAIN_H_
#define RRR_GRAPH_ODOMETRY_CHAIN_H_

#include <cmath>
#include <vector>

#include "rrr/graph/pose_graph.h"

namespace rrr {

// The odometry between consecutive poses k and k+1, composed along the chain
// with its uncertainty compounded to first order, so that the stretch of
// chain between any two poses i < j condenses into a single edge: for a
// linear-Gaussian chain, exactly the factor that marginalizing the poses
// between them leaves. Appending a step and condensing a stretch cost O(1)
// (a stretch shorter than kDirectSteps is compounded step by step, longer
// ones from prefix sums).
template <class Pose>
class OdometryChain {
 public:
  using Information = typename Constraint<Pose>::Information;
  using Covariance = Information;
  static constexpr int kDirectSteps = 64;

  // A chain of one pose.
  OdometryChain();
  // Appends the step from the last pose to a new one: measurement `z` with
  // information `information` (symmetric positive definite).
  void Append(const Pose& z, const Information& information);
  // Makes room for `poses` poses in all, so that appending moves nothing.
  void Reserve(int poses);

  int num_poses() const { return static_cast<int>(composed_.size()); }
  // The edge from pose `i` to pose `j` (0 <= i < j < num_poses()): the
  // composed odometry and the inverse of its compounded covariance.
  Constraint<Pose> Between(int i, int j) const;
  // The composed odometry from pose `i` to pose `j` (Between's measurement).
  Pose Relative(int i, int j) const {
    return composed_[i].between(composed_[j]);
  }
  // The covariance of Between(i, j)'s measurement.
  Covariance CovarianceBetween(int i, int j) const;
  // The distance travelled between poses `i` and `j` (in either order): the
  // sum of the lengths of the steps' translations between them.
  double Travelled(int i, int j) const {
    return std::abs(travelled_[j] - travelled_[i]);
  }

 private:
  std::vector<Pose> composed_;        // pose k from pose 0 at the identity
  std::vector<Pose> steps_;           // step k: from pose k to k+1
  std::vector<Covariance> step_cov_;  // covariance of step k
  std::vector<Covariance> world_sum_;  // W_k = Σ_{m<k} Ad(P_{m+1}) Σ_m Ad(·)ᵀ
  std::vector<double> travelled_;      // Σ_{m<k} |t(step m)|
};

// The steps of `graph`'s odometry: element k-1 is the edge from pose k-1 to
// pose k, for every pose k >= 1; its `from` is -1 where pose k has no
// odometry to its predecessor (it starts a chain, ChainSpansOf). An edge
// stored from the later pose to the earlier is inverted; several edges
// between the same pair are fused (to first order) into one.
template <class Pose>
std::vector<Constraint<Pose>> OdometryStepsOf(const PoseGraph<Pose>& graph);

// The chain of OdometryStepsOf(graph). Throws std::invalid_argument naming
// the pose if a pose has no odometry to its predecessor.
template <class Pose>
OdometryChain<Pose> ChainOf(const PoseGraph<Pose>& graph);

}  // namespace rrr

#endif  // RRR_GRAPH_ODOMETRY_CHAIN_H_
