// Pairwise consistency maximization, for comparison with RRR.
#ifndef RRR_ROBUST_PCM_H_
#define RRR_ROBUST_PCM_H_

#include <vector>

#include "rrr/graph/pose_graph.h"
#include "rrr/rrr/verdict.h"
#include "rrr/solver/chain_maps.h"

namespace rrr {

// PCM (Mangelson, Dominic, Eustice, Vasudevan, ICRA 2018): two loops are
// consistent when the cycle they close with the odometry between their ends
// has a Mahalanobis error under χ²(`probability`, e), with first-order
// covariances of both loops and of the condensed odometry (OdometryChain);
// the accepted loops are a maximum clique of the consistency graph. Over
// several odometry chains (ChainSpansOf) this is the paper's inter-robot
// test: loops are compared only with loops between the same two chains (or
// inside the same chain), their cycle closed by the odometry of both, and
// each such group keeps its own clique. Every
// pair is checked; the clique is found with the greedy heuristic of
// Pattabiraman et al. (which PCM's implementation offers for large graphs),
// started from the `starts` vertices of highest degree. 0.99 is the χ²
// probability of the paper's experiments.
struct PcmOptions {
  double probability = 0.99;
  int starts = 64;
};

// The decisions. If `maps` is given, it receives the chains, the pairs of
// chains with loops between them (joined when PCM keeps any, placed by the
// first kept loop) and each map minimized with the accepted loops
// (MinimizeMaps).
template <class Pose>
Verdict VerifyWithPcm(const PoseGraph<Pose>& graph, const PcmOptions& options,
                      ChainMaps<Pose>* maps = nullptr);

}  // namespace rrr

#endif  // RRR_ROBUST_PCM_H_
