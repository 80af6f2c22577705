// Dynamic covariance scaling, for comparison with RRR.
#ifndef RRR_ROBUST_DCS_H_
#define RRR_ROBUST_DCS_H_

#include <vector>

#include "rrr/graph/pose_graph.h"
#include "rrr/rrr/verdict.h"
#include "rrr/solver/convergence.h"

namespace rrr {

// Dynamic covariance scaling (Agarwal, Tipaldi, Spinello, Stachniss,
// Burgard, ICRA 2013), the closed form of switchable constraints: each
// loop's information is scaled by s² with s = min(1, 2Φ / (Φ + d²_l)),
// re-evaluated at every Gauss–Newton step from the odometry. A loop is
// accepted when its final s exceeds 0.5 (the switch value of switchable
// constraints it equals). Φ = 1 is the paper's default.
struct DcsOptions {
  double phi = 1.0;
  int max_iterations = 100;
};

// The decisions; `*map` gets the final estimate if given.
template <class Pose>
Verdict VerifyWithDcs(const PoseGraph<Pose>& graph, const DcsOptions& options,
                      std::vector<Pose>* map = nullptr,
                      MinimizeResult* minimized = nullptr);

}  // namespace rrr

#endif  // RRR_ROBUST_DCS_H_
