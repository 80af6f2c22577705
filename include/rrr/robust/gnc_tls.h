// Graduated non-convexity with a truncated least-squares cost, for
// comparison with RRR.
#ifndef RRR_ROBUST_GNC_TLS_H_
#define RRR_ROBUST_GNC_TLS_H_

#include <vector>

#include "rrr/graph/pose_graph.h"
#include "rrr/rrr/verdict.h"
#include "rrr/solver/convergence.h"

namespace rrr {

// GNC-TLS (Yang, Antonante, Tzoumas, Carlone, RA-L 2020): loop weights
// follow the GNC update of the truncated least-squares cost from a convex
// surrogate (μ small) towards the truncated cost, μ growing by `mu_factor`
// after each Gauss–Newton step; odometry is always an inlier. The truncation
// c̄² = χ²(`inlier_probability`, e) applies to a loop's d²_l (0.99, GTSAM's
// GNC default). A loop is accepted when its final weight exceeds 0.5. One
// odometry chain starts from its odometry; several from the chordal start
// of every edge (ChordalInitialization), which places each chain.
struct GncTlsOptions {
  double inlier_probability = 0.99;
  double mu_factor = 1.4;
  int max_iterations = 200;
};

// The decisions; `*map` gets the final estimate if given.
template <class Pose>
Verdict VerifyWithGncTls(const PoseGraph<Pose>& graph,
                         const GncTlsOptions& options,
                         std::vector<Pose>* map = nullptr,
                         MinimizeResult* minimized = nullptr);

}  // namespace rrr

#endif  // RRR_ROBUST_GNC_TLS_H_
