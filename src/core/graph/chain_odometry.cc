#include "rrr/graph/chain_odometry.h"

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"

namespace rrr {

template <class Pose>
int ChainOdometry<Pose>::AddChain(int pose) {
  chain_of_.push_back(num_chains());
  position_.push_back(0);
  poses_.push_back({pose});
  odometry_.emplace_back();
  return num_chains() - 1;
}

template <class Pose>
void ChainOdometry<Pose>::Append(int chain, int pose, const Pose& z,
                                 const Information& information) {
  chain_of_.push_back(chain);
  position_.push_back(static_cast<int>(poses_[chain].size()));
  poses_[chain].push_back(pose);
  odometry_[chain].Append(z, information);
}

template <class Pose>
Constraint<Pose> ChainOdometry<Pose>::Between(int i, int j) const {
  Constraint<Pose> e =
      odometry_[chain_of_[i]].Between(position_[i], position_[j]);
  e.from = i;
  e.to = j;
  return e;
}

template <class Pose>
ChainOdometry<Pose> ChainOdometryOf(const PoseGraph<Pose>& graph) {
  ChainOdometry<Pose> chains;
  if (graph.num_poses() == 0) return chains;
  chains.AddChain(0);
  const std::vector<Constraint<Pose>> steps = OdometryStepsOf(graph);
  for (int p = 1; p < graph.num_poses(); ++p) {
    const Constraint<Pose>& step = steps[p - 1];
    if (step.from < 0) {
      chains.AddChain(p);
    } else {
      chains.Append(chains.num_chains() - 1, p, step.measurement,
                    step.information);
    }
  }
  return chains;
}

template class ChainOdometry<Pose2>;
template class ChainOdometry<Pose3>;
template ChainOdometry<Pose2> ChainOdometryOf(const PoseGraph<Pose2>&);
template ChainOdometry<Pose3> ChainOdometryOf(const PoseGraph<Pose3>&);

}  // namespace rrr
