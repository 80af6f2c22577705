// Pairwise consistency maximization, for comparison with RRR.
#ifndef RRR_ROBUST_PCM_H_
#define RRR_ROBUST_PCM_H_

#include <vector>

#include "rrr/graph/pose_graph.h"
#include "rrr/rrr/verdict.h"
#include "rrr/solver/convergence.h"

namespace rrr {

// PCM (Mangelson, Dominic, Eustice, Vasudevan, ICRA 2018): two loops are
// consistent when the cycle they close with the odometry between their ends
// has a Mahalanobis error under χ²(`probability`, e), with first-order
// covariances of both loops and of the condensed odometry (OdometryChain);
// the accepted loops are a maximum clique of the consistency graph. Every
// pair is checked; the clique is found with the greedy heuristic of
// Pattabiraman et al. (which PCM's implementation offers for large graphs),
// started from the `starts` vertices of highest degree. 0.99 is the χ²
// probability of the paper's experiments.
struct PcmOptions {
  double probability = 0.99;
  int starts = 64;
};

// The decisions; `*map` gets odometry plus the accepted loops, optimized,
// if given.
template <class Pose>
Verdict VerifyWithPcm(const PoseGraph<Pose>& graph, const PcmOptions& options,
                      std::vector<Pose>* map = nullptr,
                      MinimizeResult* minimized = nullptr);

}  // namespace rrr

#endif  // RRR_ROBUST_PCM_H_
