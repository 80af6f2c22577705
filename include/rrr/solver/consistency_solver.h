// What RRR asks of a solver: solve with a subset of loops, report errors.
#ifndef RRR_SOLVER_CONSISTENCY_SOLVER_H_
#define RRR_SOLVER_CONSISTENCY_SOLVER_H_

#include <vector>

namespace rrr {

// The errors of one consistency solve.
struct SubsetErrors {
  // D²_G: summed error of all active edges (odometry and active loops).
  double total_chi2 = 0.0;
  // n_G: number of active edges.
  int num_edges = 0;
  // The active edges that can carry error: the odometry edges of the stretch
  // of chain between the first and last pose the active loops reach, and the
  // loops. Every other odometry edge keeps zero error. 0 with no loops.
  int num_spanned_edges = 0;
  // d²_l of each active loop, in the order the loops were given.
  std::vector<double> loop_chi2;
  // False if the linear system could not be solved (then the errors are +inf).
  bool solved = true;
};

// The solve used by every RRR test. Solve() may be called from several
// threads at once (RrrOptions::threads > 1).
class ConsistencySolver {
 public:
  virtual ~ConsistencySolver() = default;
  // Resets every pose to the odometry initial estimate, runs a fixed number
  // of iterations (Gauss–Newton or Levenberg–Marquardt) with odometry and
  // `active_loops` (indices of loop candidates) active and the first pose
  // fixed, and returns the errors at the resulting estimate.
  virtual SubsetErrors Solve(const std::vector<int>& active_loops) = 0;
  // Dimension e of one edge residual (3 in 2D, 6 in 3D).
  virtual int residual_dim() const = 0;
};

}  // namespace rrr

#endif  // RRR_SOLVER_CONSISTENCY_SOLVER_H_
