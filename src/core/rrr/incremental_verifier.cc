#include "rrr/rrr/incremental_verifier.h"

#include <algorithm>
#include <atomic>
#include <stdexcept>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/rrr/batch_verifier.h"
#include "rrr/rrr/consistency_tests.h"
#include "rrr/solver/gauss_newton.h"
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

const char* ToString(LoopState state) {
  switch (state) {
    case LoopState::kPending:
      return "pending";
    case LoopState::kAccepted:
      return "accepted";
    case LoopState::kRejected:
      return "rejected";
  }
  return "unknown";
}

template <class Pose>
IncrementalVerifier<Pose>::IncrementalVerifier(const RrrOptions& options)
    : options_(options), chi2_(options.alpha) {
  const std::string problem = options.Validate();
  if (!problem.empty()) throw std::invalid_argument(problem);
}

template <class Pose>
void IncrementalVerifier<Pose>::AddFirstPose(PoseId id, const Pose& pose) {
  if (graph_.num_poses() > 0) throw std::logic_error("the chain has started");
  graph_.AddPose(id, pose);
  ApplyWaiting();
}

template <class Pose>
PoseId IncrementalVerifier<Pose>::AddOdometry(const Pose& z,
                                              const Information& information) {
  if (graph_.num_poses() == 0) {
    throw std::logic_error("odometry before the first pose");
  }
  const int from = graph_.num_poses() - 1;
  const PoseId id = graph_.ids().back() + 1;
  const int to = graph_.AddPose(id, graph_.estimates().back() * z);
  graph_.AddEdge(Constraint<Pose>{from, to, z, information});
  ApplyWaiting();
  return id;
}

template <class Pose>
int IncrementalVerifier<Pose>::AddLoop(PoseId a, PoseId b, const Pose& z,
                                       const Information& information) {
  if (std::llabs(a - b) < 2) {
    throw std::invalid_argument("a loop candidate needs |a - b| > 1, got " +
                                std::to_string(a) + " and " +
                                std::to_string(b));
  }
  if (graph_.num_poses() > 0 && std::min(a, b) < graph_.ids().front()) {
    throw std::invalid_argument("pose " + std::to_string(std::min(a, b)) +
                                " precedes the first pose " +
                                std::to_string(graph_.ids().front()));
  }
  candidates_.push_back(Candidate{a, b, z, information});
  waiting_.push_back(num_candidates() - 1);
  ApplyWaiting();
  return num_candidates() - 1;
}

template <class Pose>
void IncrementalVerifier<Pose>::ApplyWaiting() {
  auto still_waiting = waiting_.begin();
  for (const int c : waiting_) {
    Candidate& cand = candidates_[c];
    const int from = graph_.IndexOf(cand.a), to = graph_.IndexOf(cand.b);
    if (from < 0 || to < 0) {
      *still_waiting++ = c;
      continue;
    }
    graph_.AddEdge(
        Constraint<Pose>{from, to, cand.measurement, cand.information});
    cand.loop = static_cast<int>(graph_.loops().size()) - 1;
    candidate_of_loop_.push_back(c);
  }
  waiting_.erase(still_waiting, waiting_.end());
}

template <class Pose>
int IncrementalVerifier<Pose>::cluster_of(int candidate) const {
  const int loop = candidates_.at(candidate).loop;
  return loop < 0 || loop >= static_cast<int>(cluster_of_loop_.size())
             ? -1
             : cluster_of_loop_[loop];
}

template <class Pose>
std::pair<PoseId, PoseId> IncrementalVerifier<Pose>::ends_of(
    int candidate) const {
  return {candidates_.at(candidate).a, candidates_.at(candidate).b};
}

template <class Pose>
std::vector<int> IncrementalVerifier<Pose>::AcceptedLoops() const {
  std::vector<int> accepted;
  for (size_t loop = 0; loop < candidate_of_loop_.size(); ++loop) {
    if (candidates_[candidate_of_loop_[loop]].state == LoopState::kAccepted) {
      accepted.push_back(static_cast<int>(loop));
    }
  }
  return accepted;
}

template <class Pose>
std::vector<DecisionChange> IncrementalVerifier<Pose>::Update() {
  return Judge(false);
}

template <class Pose>
std::vector<DecisionChange> IncrementalVerifier<Pose>::Finish() {
  return Judge(true);
}

template <class Pose>
std::vector<DecisionChange> IncrementalVerifier<Pose>::Judge(bool finish) {
  // Clusters change only when loops were added.
  if (cluster_of_loop_.size() != graph_.loops().size()) {
    clusters_ = ClusterInBatchOrder(LoopEnds(graph_), options_.cluster_window,
                                    &cluster_of_loop_);
  }
  const PoseId newest = graph_.num_poses() > 0 ? graph_.ids().back() : 0;
  std::vector<std::vector<int>> ready;
  for (const Cluster& c : clusters_) {
    if (finish || newest - c.start_high >= options_.cluster_window) {
      ready.push_back(c.loops);
    }
  }
  if (ready == judged_) return {};
  judged_ = ready;

  GaussNewton<Pose> gauss_newton(graph_, options_.iterations);
  CountingSolver solver(gauss_newton);
  const int e = solver.residual_dim();
  const int odometry = static_cast<int>(graph_.odometry().size());
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
  num_solves_ += solver.count();

  std::vector<LoopState> next(candidates_.size(), LoopState::kPending);
  for (const auto& members : ready) {
    for (const int loop : members) {
      next[candidate_of_loop_[loop]] = LoopState::kRejected;
    }
  }
  for (size_t c = 0; c < survivors.size(); ++c) {
    if (!good[c]) continue;
    for (const int loop : survivors[c]) {
      next[candidate_of_loop_[loop]] = LoopState::kAccepted;
    }
  }
  std::vector<DecisionChange> changes;
  for (size_t c = 0; c < candidates_.size(); ++c) {
    if (next[c] != candidates_[c].state) {
      changes.push_back({static_cast<int>(c), candidates_[c].state, next[c]});
      candidates_[c].state = next[c];
    }
  }
  return changes;
}

template class IncrementalVerifier<Pose2>;
template class IncrementalVerifier<Pose3>;

}  // namespace rrr
