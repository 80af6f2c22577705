#include "rrr/rrr/published/incremental_verifier.h"

#include <algorithm>
#include <atomic>
#include <stdexcept>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/rrr/published/consistency_tests.h"
#include "rrr/rrr/verdict.h"
#include "rrr/solver/pose_graph_solver.h"
#include "rrr/solver/solve_in_parallel.h"

namespace rrr {
namespace {

// Counts the solves of a solver it wraps.
class CountingSolver : public ConsistencySolver {
 public:
  explicit CountingSolver(ConsistencySolver& solver) : solver_(solver) {}
  SubsetErrors Solve(const std::vector<int>& active_loops) override {
    ++count_;
    return solver_.Solve(active_loops);
  }
  int residual_dim() const override { return solver_.residual_dim(); }
  int count() const { return count_; }

 private:
  ConsistencySolver& solver_;
  std::atomic<int> count_{0};
};

}  // namespace

template <class Pose>
IncrementalVerifier<Pose>::IncrementalVerifier(const RrrOptions& options)
    : OnlineVerifier<Pose>(options), options_(options), chi2_(options.alpha) {
  const std::string problem = options.Validate();
  if (!problem.empty()) throw std::invalid_argument(problem);
}

template <class Pose>
std::vector<Pose> IncrementalVerifier<Pose>::Map() {
  if (this->graph().num_poses() == 0) return {};
  const PoseGraphSolver<Pose> solver(this->graph(), options_.iterations,
                                     options_.steps);
  return solver.Optimize(this->AcceptedLoops(), ConvergenceOptions());
}

template <class Pose>
std::vector<DecisionChange> IncrementalVerifier<Pose>::Judge(bool finish) {
  // Clusters change only when loops were added.
  const PoseGraph<Pose>& graph = this->graph();
  if (this->cluster_of_loop_.size() != graph.loops().size()) {
    const std::vector<int> before = this->cluster_of_loop_;
    clusters_ = ClusterInBatchOrder(LoopEnds(graph), options_.cluster_window,
                                    &this->cluster_of_loop_);
    if (!std::equal(before.begin(), before.end(),
                    this->cluster_of_loop_.begin())) {
      this->CountReclustering();
    }
  }
  const PoseId newest = graph.num_poses() > 0 ? graph.ids().back() : 0;
  std::vector<std::vector<int>> ready;
  for (const Cluster& c : clusters_) {
    if (finish || newest - c.start_high >=
                      options_.cluster_window + options_.decision_delay) {
      ready.push_back(c.loops);
    }
  }
  if (ready == judged_) return {};
  judged_ = ready;

  PoseGraphSolver<Pose> base_solver(graph, options_.iterations, options_.steps);
  CountingSolver solver(base_solver);
  const int e = solver.residual_dim();
  const int odometry = static_cast<int>(graph.odometry().size());
  std::vector<std::vector<int>> unsolved;
  for (const std::vector<int>& members : ready) {
    if (intra_errors_.count(members) == 0) unsolved.push_back(members);
  }
  std::vector<SubsetErrors> solved =
      SolveInParallel(solver, unsolved, options_.threads);
  for (size_t k = 0; k < unsolved.size(); ++k) {
    intra_errors_.emplace(std::move(unsolved[k]), std::move(solved[k]));
  }
  std::vector<std::vector<int>> survivors;
  for (const std::vector<int>& members : ready) {
    // The solve's errors do not change as the chain grows; its edge count does.
    SubsetErrors errors = intra_errors_.at(members);
    errors.num_edges = odometry + static_cast<int>(members.size());
    std::vector<int> kept =
        IntraClusterSurvivors(members, errors, e, chi2_, options_.span_gate);
    if (!kept.empty()) survivors.push_back(std::move(kept));
  }
  const std::vector<bool> good = InterClusterConsistent(
      survivors, solver, chi2_, options_.span_gate, options_.threads);
  this->CountSolves(solver.count());

  std::vector<LoopState> next(this->num_candidates(), LoopState::kPending);
  for (const auto& members : ready) {
    for (const int loop : members) {
      next[this->candidate_of_loop(loop)] = LoopState::kRejected;
    }
  }
  for (size_t c = 0; c < survivors.size(); ++c) {
    if (!good[c]) continue;
    for (const int loop : survivors[c]) {
      next[this->candidate_of_loop(loop)] = LoopState::kAccepted;
    }
  }
  return this->SetStates(next);
}

template class IncrementalVerifier<Pose2>;
template class IncrementalVerifier<Pose3>;

}  // namespace rrr
