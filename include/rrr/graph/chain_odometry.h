// The odometry of the chains of a graph whose poses arrive side by side:
// robots of a fleet, or sessions of one robot.
#ifndef RRR_GRAPH_CHAIN_ODOMETRY_H_
#define RRR_GRAPH_CHAIN_ODOMETRY_H_

#include <cstdint>
#include <vector>

#include "rrr/graph/odometry_chain.h"
#include "rrr/graph/pose_graph.h"

namespace rrr {

// Which chain each pose of a graph is in and where, and each chain's
// odometry condensed (OdometryChain). Poses are the graph's indices, in the
// order they arrived: the chains' poses may interleave. A chain's poses are
// joined by odometry; chains are joined to each other only by loops.
template <class Pose>
class ChainOdometry {
 public:
  using Information = typename Constraint<Pose>::Information;

  // Starts a new chain at pose `pose`, the next pose index; returns the
  // chain's index (0, 1, ... in order).
  int AddChain(int pose);
  // Appends pose `pose`, the next pose index, to chain `chain`, reached from
  // its last pose by odometry `z` with `information`.
  void Append(int chain, int pose, const Pose& z,
              const Information& information);

  int num_chains() const { return static_cast<int>(poses_.size()); }
  int num_poses() const { return static_cast<int>(chain_of_.size()); }
  int chain_of(int pose) const { return chain_of_[pose]; }
  // The pose's place in its chain (0 for the chain's first).
  int position(int pose) const { return position_[pose]; }
  // The poses of chain `chain`, in order.
  const std::vector<int>& poses(int chain) const { return poses_[chain]; }
  const OdometryChain<Pose>& odometry(int chain) const {
    return odometry_[chain];
  }
  // An order of the poses chain by chain, each chain's in order: a key
  // that sorts a chain's poses together and in their order.
  std::int64_t Key(int pose) const {
    return (static_cast<std::int64_t>(chain_of_[pose]) << 32) | position_[pose];
  }
  // The pose whose Key is `key`.
  int PoseOfKey(std::int64_t key) const {
    return poses_[key >> 32][static_cast<int>(key & 0xffffffff)];
  }

  // The condensed odometry from pose `i` to pose `j` of the same chain, `i`
  // earlier (OdometryChain::Between), as an edge from `i` to `j`.
  Constraint<Pose> Between(int i, int j) const;
  // The composed odometry from pose `i` to pose `j` of the same chain.
  Pose Relative(int i, int j) const {
    return odometry_[chain_of_[i]].Relative(position_[i], position_[j]);
  }
  // The way travelled between poses `i` and `j` of the same chain.
  double Travelled(int i, int j) const {
    return odometry_[chain_of_[i]].Travelled(position_[i], position_[j]);
  }

 private:
  std::vector<int> chain_of_, position_;  // by pose
  std::vector<std::vector<int>> poses_;   // by chain
  std::vector<OdometryChain<Pose>> odometry_;
};

// The chains of `graph` (ChainSpansOf: laid end to end, a new one at every
// pose without odometry to its predecessor) with their odometry
// (OdometryStepsOf).
template <class Pose>
ChainOdometry<Pose> ChainOdometryOf(const PoseGraph<Pose>& graph);

}  // namespace rrr

#endif  // RRR_GRAPH_CHAIN_ODOMETRY_H_
