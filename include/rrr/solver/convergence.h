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

// Why a minimization stopped.
enum class StopReason {
  kNotRun,            // no iteration was asked for
  kRelativeDecrease,  // the last step lowered the error by less than
                      // ConvergenceOptions::relative_decrease of it
  kStationary,        // the linear model predicts a decrease below that (the
                      // gradient vanishes): a minimum to that precision
  kNoAcceptableStep,  // no damped step lowers the error
  kIterationLimit,    // ConvergenceOptions::max_iterations reached
  kOutOfReach,        // the error could not come down to the level asked
                      // for within the iterations left (LocalProblem::Minimize)
  kNotSolved,         // a linear system could not be solved
};
// "not_run", "relative_decrease", "stationary", "no_acceptable_step",
// "iteration_limit", "out_of_reach" or "not_solved".
const char* ToString(StopReason reason);

// What a minimization did.
struct MinimizeResult {
  StopReason stop = StopReason::kNotRun;
  int iterations = 0;
  // The last step decreased the error by less than the relative threshold,
  // or no step could decrease it by that much (false: stopped by the
  // iteration limit or out of reach, or not solved).
  bool converged = false;
  // False if a linear system could not be solved (the estimate is then the
  // best one reached before).
  bool solved = true;
  double initial_chi2 = 0.0;
  double final_chi2 = 0.0;
};

}  // namespace rrr

#endif  // RRR_SOLVER_CONVERGENCE_H_
