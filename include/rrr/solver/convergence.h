// When an iterative minimization stops, and what it did.
#ifndef RRR_SOLVER_CONVERGENCE_H_
#define RRR_SOLVER_CONVERGENCE_H_

namespace rrr {

// How a fixed number of iterations (RRR's consistency solves) step.
enum class SolveSteps {
  kGaussNewton,  // plain steps, as RRR is published
  kTrustRegion,  // Levenberg–Marquardt (TrustRegion): never raises the error
};

// When a minimization stops.
struct ConvergenceOptions {
  int max_iterations = 100;
  // Stop when the error decreases by less than this fraction in a step.
  double relative_decrease = 1e-9;
};

// What a minimization did.
struct MinimizeResult {
  int iterations = 0;
  // The last step decreased the error by less than the relative threshold,
  // or no step could decrease it by that much (false: stopped by the
  // iteration limit, or not solved).
  bool converged = false;
  // False if a linear system could not be solved (the estimate is then the
  // best one reached before).
  bool solved = true;
  double initial_chi2 = 0.0;
  double final_chi2 = 0.0;
};

}  // namespace rrr

#endif  // RRR_SOLVER_CONVERGENCE_H_
