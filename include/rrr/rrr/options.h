// Parameters of RRR.
#ifndef RRR_RRR_OPTIONS_H_
#define RRR_RRR_OPTIONS_H_

#include <string>

#include "rrr/solver/convergence.h"

namespace rrr {

// Which decision procedure judges the clusters.
enum class Procedure {
  // RRR as published (RRR_ALGORITHM.md §2–4, BatchVerifier and
  // IncrementalVerifier): every decision re-runs the joint tests over all
  // clusters, each solve from odometry.
  kPublished,
  // Each cluster judged once against a maintained map (MapVerifier).
  kMap,
};
const char* ToString(Procedure procedure);
// Parses "published" or "map"; returns false for anything else.
bool ParseProcedure(const std::string& name, Procedure* procedure);

struct RrrOptions {
  Procedure procedure = Procedure::kMap;
  // t: loops whose ends are closer than this many poses may share a cluster.
  // 10 suits keyframe graphs; 50 suits Bicocca 25b (5 Hz odometry, 1 Hz loops).
  int cluster_window = 10;
  // k: iterations of each consistency test.
  int iterations = 4;
  // The published procedure: how those k iterations step. Gauss–Newton as
  // published; Levenberg–Marquardt steps never raise the error, so a solve that
  // plain steps would throw off from odometry stays near it.
  SolveSteps steps = SolveSteps::kGaussNewton;
  // α: the χ² quantile of every gate.
  double alpha = 0.95;
  // Off (the method as published): the total error D²_G of a solve is gated
  // by χ²(α, e·n_G) over every edge of the graph. On: by χ²(α, e·n_S) over
  // the n_S edges that can carry error (the stretch of odometry the active
  // loops span, and the loops; see SubsetErrors), so a cluster that bends a
  // short stretch of odometry far is not let through by the many edges
  // elsewhere that it leaves untouched. Not part of the paper; measured in
  // BENCHMARKS.md.
  bool span_gate = false;
  // How many consistency solves may run at once. Decisions do not depend on
  // it: the intra-cluster tests run side by side, and the inter-cluster
  // procedure solves ahead (at most 4 joint solves at once) the sets it would
  // reach by setting aside clusters in their current order of inconsistency,
  // using only the solves the one-at-a-time procedure would have made.
  int threads = 1;

  // Bounds of the candidates waiting for a pose (OnlineVerifier::AddLoop):
  // one may name a pose at most `max_future_poses` ids past the newest, and
  // at most `max_waiting` may wait at once; others are refused.
  int max_future_poses = 1000;
  int max_waiting = 10000;
  // Online only: a cluster is judged this many poses later than it is ready
  // (still as of the pose it became ready at), so that its loops may arrive
  // that much after their later pose (a front-end's latency, or a loop topic
  // that lags the odometry) and still join it. 0 (default): judged as soon
  // as ready. A batch run's decisions do not depend on it.
  int decision_delay = 0;

  // The map procedure only (MapVerifier).
  // s: every gate compares an error with s·χ²(α, dof). 1 trusts the
  // information matrices as given; 0 estimates s from the data
  // (NoiseScaleEstimate).
  double noise_scale = 0.0;
  // With an estimated scale, the gates use this many times the estimate:
  // the estimate is of the typical error, the gates must pass the loops'
  // heavier tails (the measured trade-off is in BENCHMARKS.md).
  double noise_margin = 5.0;
  // Hops (along the chain between junctions, or across an accepted loop)
  // around a cluster's ends that a local solve minimizes over.
  int map_radius = 6;
  // A local solve's region stops growing after the hop layer that brings it
  // to this many junctions, so that no decision costs more than a solve of
  // about that size, however large the map (the whole map is minimized only
  // at optimize_every).
  int map_junctions = 1000;
  // The whole map is minimized after this many accepted clusters, or after
  // the accepted clusters grew by optimize_growth if that is more: often
  // while the map is small, a bounded share of the work when it is large.
  int optimize_every = 10;
  double optimize_growth = 0.1;
  // How the map procedure's minimizations stop.
  ConvergenceOptions convergence{20, 1e-3};

  // Returns an empty string if the options are usable, otherwise a message
  // naming the first bad option.
  std::string Validate() const;
};

// The options as one line of `name=value` pairs, every field, doubles to
// the last bit: what a session database records. ParseOptionsText reads it
// back (a name it does not list keeps its default) and throws
// std::invalid_argument naming a pair that is not `name=value`, an unknown
// name or a value that is not one.
std::string OptionsText(const RrrOptions& options);
RrrOptions ParseOptionsText(const std::string& text);

}  // namespace rrr

#endif  // RRR_RRR_OPTIONS_H_
