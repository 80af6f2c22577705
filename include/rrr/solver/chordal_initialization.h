// A start for minimizing a pose graph that does not depend on the odometry
// alone: chordal relaxation of the rotations, then the translations.
#ifndef RRR_SOLVER_CHORDAL_INITIALIZATION_H_
#define RRR_SOLVER_CHORDAL_INITIALIZATION_H_

#include <vector>

#include "rrr/graph/pose_graph.h"

namespace rrr {

// An estimate of every pose of `graph` from its odometry and `loops`
// (indices into graph.loops()) by chordal relaxation (Carlone et al., ICRA
// 2015; GTSAM's InitializePose3): first the rotations, as unconstrained
// d×d matrices that fit R_j = R_i·R_ij in the least-squares sense (each edge
// weighted by the mean of its rotation information), each projected to the
// nearest rotation; then, with the rotations held, the translations that
// fit t_j − t_i = R_i·t_ij weighted by each edge's translation information.
// Both are linear, so the result depends on no initial estimate; the first
// pose keeps graph.estimates()[0]. Every pose must be reached from the first
// by the edges used (a single odometry chain is). Throws
// std::runtime_error if one is not (PoseGraph::CheckConnected) or a linear
// system cannot be solved.
template <class Pose>
std::vector<Pose> ChordalInitialization(const PoseGraph<Pose>& graph,
                                        const std::vector<int>& loops);

}  // namespace rrr

#endif  // RRR_SOLVER_CHORDAL_INITIALIZATION_H_
