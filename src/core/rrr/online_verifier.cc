#include "rrr/rrr/online_verifier.h"

#include <algorithm>
#include <cstdlib>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/graph/chain_spans.h"
#include "rrr/graph/odometry_chain.h"
#include "rrr/io/symbol_key.h"

namespace rrr {

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
OnlineVerifier<Pose>::OnlineVerifier(const RrrOptions& bounds)
    : max_future_poses_(bounds.max_future_poses),
      max_waiting_(bounds.max_waiting) {}

template <class Pose>
void OnlineVerifier<Pose>::AddFirstPose(PoseId id, const Pose& pose) {
  if (graph_.num_poses() > 0) throw std::logic_error("the chain has started");
  AddChain(id, pose);
}

template <class Pose>
int OnlineVerifier<Pose>::AddChain(PoseId id, const Pose& pose) {
  if (num_chains() > 0 && !JudgesSeveralChains()) {
    throw std::logic_error("this procedure judges one odometry chain");
  }
  const int p = graph_.AddPose(id, pose);
  const int chain = chains_.AddChain(p);
  chain_of_first_id_[id] = chain;
  ApplyWaiting();
  return chain;
}

template <class Pose>
PoseId OnlineVerifier<Pose>::AddOdometry(int chain, const Pose& z,
                                         const Information& information) {
  if (chain < 0 || chain >= num_chains()) {
    throw std::out_of_range("chain " + std::to_string(chain) +
                            " does not exist");
  }
  const int from = chains_.poses(chain).back();
  const PoseId id = graph_.ids()[from] + 1;
  if (graph_.IndexOf(id) >= 0) {
    throw std::logic_error("the next pose of chain " + std::to_string(chain) +
                           ", id " + std::to_string(id) +
                           ", is a pose of another chain");
  }
  const int to = graph_.AddPose(id, graph_.estimates()[from] * z);
  graph_.AddEdge(Constraint<Pose>{from, to, z, information});
  chains_.Append(chain, to, z, information);
  ApplyWaiting();
  return id;
}

template <class Pose>
PoseId OnlineVerifier<Pose>::AddOdometry(const Pose& z,
                                         const Information& information) {
  if (num_chains() == 0) {
    throw std::logic_error("odometry before the first pose");
  }
  return AddOdometry(num_chains() - 1, z, information);
}

template <class Pose>
int OnlineVerifier<Pose>::AddLoop(PoseId a, PoseId b, const Pose& z,
                                  const Information& information) {
  const std::string pair = std::to_string(a) + " -> " + std::to_string(b);
  if (a == b) {
    throw DegenerateCandidate(CandidateDefect::kSelfLoop,
                              "candidate " + pair + " links a pose to itself");
  }
  if (std::llabs(a - b) < 2) {
    throw DegenerateCandidate(
        CandidateDefect::kConsecutivePoses,
        "candidate " + pair + " links consecutive poses (that is odometry)");
  }
  if (num_chains() > 0) {
    const PoseId first = chain_of_first_id_.begin()->first;
    if (std::min(a, b) < first) {
      throw DegenerateCandidate(
          CandidateDefect::kUnknownPose,
          "candidate " + pair + ": pose " + std::to_string(std::min(a, b)) +
              " precedes the first pose " + std::to_string(first));
    }
    for (const PoseId id : {std::max(a, b), std::min(a, b)}) {
      // The chain whose ids `id` falls among: the last to start before it.
      const int chain = std::prev(chain_of_first_id_.upper_bound(id))->second;
      const PoseId newest = graph_.ids()[chains_.poses(chain).back()];
      if (id > newest + max_future_poses_) {
        throw DegenerateCandidate(
            CandidateDefect::kTooFarAhead,
            "candidate " + pair + ": pose " + std::to_string(id) +
                " is more than " + std::to_string(max_future_poses_) +
                " poses past the newest, " + std::to_string(newest));
      }
    }
  }
  const bool waits = graph_.IndexOf(a) < 0 || graph_.IndexOf(b) < 0;
  if (waits && num_waiting() >= max_waiting_) {
    throw DegenerateCandidate(CandidateDefect::kWaitingFull,
                              "candidate " + pair + " would wait while " +
                                  std::to_string(max_waiting_) +
                                  " candidates already wait");
  }
  std::vector<int>& same_pair = by_pair_[{a, b}];
  for (const int c : same_pair) {
    const Candidate& other = candidates_[c];
    if (other.measurement.Log() == z.Log() &&
        other.information == information) {
      throw DegenerateCandidate(
          CandidateDefect::kDuplicate,
          "candidate " + pair + " repeats candidate " + std::to_string(c));
    }
  }
  same_pair.push_back(num_candidates());
  candidates_.push_back(Candidate{a, b, z, information});
  ++count_by_state_[static_cast<int>(LoopState::kPending)];
  waiting_.push_back(num_candidates() - 1);
  ApplyWaiting();
  return num_candidates() - 1;
}

template <class Pose>
void OnlineVerifier<Pose>::ApplyWaiting() {
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
    poses_at_arrival_.push_back(
        std::min(graph_.num_poses(), std::max(from, to) + 1));
  }
  waiting_.erase(still_waiting, waiting_.end());
}

template <class Pose>
std::vector<Pose> OnlineVerifier<Pose>::MapAt(const std::vector<int>& poses) {
  const std::vector<Pose> map = Map();
  std::vector<Pose> out;
  out.reserve(poses.size());
  for (const int p : poses) out.push_back(map.at(p));
  return out;
}

template <class Pose>
int OnlineVerifier<Pose>::cluster_of(int candidate) const {
  const int loop = loop_of(candidate);
  return loop < 0 || loop >= static_cast<int>(cluster_of_loop_.size())
             ? -1
             : cluster_of_loop_[loop];
}

template <class Pose>
std::pair<PoseId, PoseId> OnlineVerifier<Pose>::ends_of(int candidate) const {
  return {candidates_.at(candidate).a, candidates_.at(candidate).b};
}

template <class Pose>
std::vector<int> OnlineVerifier<Pose>::AcceptedLoops() const {
  std::vector<int> accepted;
  for (size_t loop = 0; loop < candidate_of_loop_.size(); ++loop) {
    if (candidates_[candidate_of_loop_[loop]].state == LoopState::kAccepted) {
      accepted.push_back(static_cast<int>(loop));
    }
  }
  return accepted;
}

template <class Pose>
bool OnlineVerifier<Pose>::SavedUnderSameOptions(const std::string&) const {
  throw std::runtime_error("this verifier does not restore saved states");
}

template <class Pose>
void OnlineVerifier<Pose>::RestoreState(const std::string&) {
  throw std::logic_error("this verifier does not restore saved states");
}

template <class Pose>
void OnlineVerifier<Pose>::SaveRecord(ByteWriter* out) const {
  out->Int(graph_.num_poses());
  out->Int(static_cast<std::int64_t>(graph_.loops().size()));
  std::string states;
  for (const Candidate& c : candidates_) {
    states.push_back(static_cast<char>(c.state));
  }
  out->Text(states);
  out->Int(num_solves_);
  out->Int(num_reclusterings_);
  out->Ints(cluster_of_loop_);
}

template <class Pose>
void OnlineVerifier<Pose>::RestoreRecord(ByteReader* in) {
  const std::int64_t poses = in->Int("the number of poses");
  const std::int64_t loops = in->Int("the number of loops");
  const std::string states = in->Text("the candidates' states");
  if (poses != graph_.num_poses() ||
      loops != static_cast<std::int64_t>(graph_.loops().size()) ||
      states.size() != candidates_.size()) {
    throw std::runtime_error(
        "the state was saved with " + std::to_string(poses) + " poses, " +
        std::to_string(loops) + " loops and " + std::to_string(states.size()) +
        " candidates, but the verifier has " +
        std::to_string(graph_.num_poses()) + ", " +
        std::to_string(graph_.loops().size()) + " and " +
        std::to_string(candidates_.size()));
  }
  std::vector<DecisionChange> ignored;
  for (size_t c = 0; c < states.size(); ++c) {
    const int state = static_cast<unsigned char>(states[c]);
    if (state > static_cast<int>(LoopState::kRejected)) {
      throw std::runtime_error("candidate " + std::to_string(c) +
                               " has the unknown state " +
                               std::to_string(state));
    }
    SetState(static_cast<int>(c), static_cast<LoopState>(state), &ignored);
  }
  num_solves_ = static_cast<int>(in->Int("the number of solves"));
  num_reclusterings_ = static_cast<int>(in->Int("the reclusterings"));
  cluster_of_loop_ = in->Ints("the loops' clusters");
  if (cluster_of_loop_.size() > graph_.loops().size()) {
    throw std::runtime_error(
        "the state clusters more loops than the graph has");
  }
}

template <class Pose>
std::vector<DecisionChange> OnlineVerifier<Pose>::SetStates(
    const std::vector<LoopState>& next) {
  std::vector<DecisionChange> changes;
  for (size_t c = 0; c < candidates_.size(); ++c) {
    SetState(static_cast<int>(c), next[c], &changes);
  }
  return changes;
}

template <class Pose>
void OnlineVerifier<Pose>::SetState(int candidate, LoopState state,
                                    std::vector<DecisionChange>* changes) {
  Candidate& c = candidates_[candidate];
  if (c.state == state) return;
  changes->push_back({candidate, c.state, state});
  --count_by_state_[static_cast<int>(c.state)];
  ++count_by_state_[static_cast<int>(state)];
  c.state = state;
}

template <class Pose>
std::vector<int> ArrivalOrder(const PoseGraph<Pose>& graph, bool side_by_side) {
  std::vector<int> order(graph.num_poses());
  std::iota(order.begin(), order.end(), 0);
  if (!side_by_side) return order;
  // Each pose at its robot's time: its index below the robot's letter (a
  // robot's sessions one after another), else its place in its chain.
  const std::vector<ChainSpan> spans = ChainSpansOf(graph);
  std::vector<std::pair<std::int64_t, int>> time(graph.num_poses());
  for (int p = 0; p < graph.num_poses(); ++p) {
    const int chain = ChainHolding(spans, p);
    const auto symbol = AsSymbol(graph.ids()[p]);
    time[p] = {symbol ? static_cast<std::int64_t>(symbol->index)
                      : p - spans[chain].first,
               chain};
  }
  std::stable_sort(order.begin(), order.end(),
                   [&](int p, int q) { return time[p] < time[q]; });
  return order;
}

template <class Pose>
std::vector<int> FeedInArrivalOrder(
    const PoseGraph<Pose>& graph, OnlineVerifier<Pose>* verifier,
    int update_every,
    const std::function<void(const std::vector<DecisionChange>&)>& on_changes,
    int loop_lag, const std::vector<int>& order, bool finish) {
  const std::vector<int> arrival =
      order.empty() ? ArrivalOrder(graph, false) : order;
  const int n = static_cast<int>(arrival.size());
  std::vector<int> arrived_at(graph.num_poses(), -1);
  for (int k = 0; k < n; ++k) arrived_at[arrival[k]] = k;
  const std::vector<Constraint<Pose>> steps = OdometryStepsOf(graph);
  std::vector<std::vector<int>> ending_at(n);
  for (size_t k = 0; k < graph.loops().size(); ++k) {
    const auto& e = graph.loops()[k];
    if (arrived_at[e.from] < 0 || arrived_at[e.to] < 0) continue;
    const int lag = static_cast<int>(k) % (loop_lag + 1);
    ending_at[std::min(std::max(arrived_at[e.from], arrived_at[e.to]) + lag,
                       n - 1)]
        .push_back(static_cast<int>(k));
  }
  const auto report = [&](const std::vector<DecisionChange>& changes) {
    if (on_changes) on_changes(changes);
  };
  std::vector<int> loop_of_candidate;
  std::vector<int> chain_of(graph.num_poses(), -1);  // the verifier's chains
  verifier->Reserve(n, static_cast<int>(graph.loops().size()));
  for (int k = 0; k < n; ++k) {
    const int p = arrival[k];
    if (p == 0 || steps[p - 1].from < 0) {
      chain_of[p] = verifier->AddChain(graph.ids()[p], graph.estimates()[p]);
    } else {
      chain_of[p] = chain_of[p - 1];
      verifier->AddOdometry(chain_of[p], steps[p - 1].measurement,
                            steps[p - 1].information);
    }
    for (const int loop : ending_at[k]) {
      const auto& e = graph.loops()[loop];
      verifier->AddLoop(graph.ids()[e.from], graph.ids()[e.to], e.measurement,
                        e.information);
      loop_of_candidate.push_back(loop);
    }
    if ((k + 1) % update_every == 0) report(verifier->Update());
  }
  if (finish) report(verifier->Finish());
  return loop_of_candidate;
}

template <class Pose>
Verdict VerdictOf(const OnlineVerifier<Pose>& verifier,
                  const std::vector<int>& loop_of_candidate, int num_loops) {
  Verdict verdict;
  verdict.cluster_of_loop.assign(num_loops, -1);
  verdict.reasons.resize(num_loops);
  verdict.clusters.resize(verifier.num_clusters());
  for (int c = 0; c < verifier.num_candidates(); ++c) {
    const int k = loop_of_candidate[c];
    if (k < 0) continue;
    verdict.cluster_of_loop[k] = verifier.cluster_of(c);
    verdict.reasons[k] = verifier.reason(c);
    (verifier.state(c) == LoopState::kAccepted ? verdict.accepted
                                               : verdict.rejected)
        .push_back(k);
  }
  std::sort(verdict.accepted.begin(), verdict.accepted.end());
  std::sort(verdict.rejected.begin(), verdict.rejected.end());
  for (int k = 0; k < num_loops; ++k) {
    const int cluster = verdict.cluster_of_loop[k];
    if (cluster >= 0) verdict.clusters[cluster].loops.push_back(k);
  }
  return verdict;
}

template class OnlineVerifier<Pose2>;
template class OnlineVerifier<Pose3>;
template std::vector<int> ArrivalOrder(const PoseGraph<Pose2>&, bool);
template std::vector<int> ArrivalOrder(const PoseGraph<Pose3>&, bool);
template std::vector<int> FeedInArrivalOrder(
    const PoseGraph<Pose2>&, OnlineVerifier<Pose2>*, int,
    const std::function<void(const std::vector<DecisionChange>&)>&, int,
    const std::vector<int>&, bool);
template std::vector<int> FeedInArrivalOrder(
    const PoseGraph<Pose3>&, OnlineVerifier<Pose3>*, int,
    const std::function<void(const std::vector<DecisionChange>&)>&, int,
    const std::vector<int>&, bool);
template Verdict VerdictOf(const OnlineVerifier<Pose2>&,
                           const std::vector<int>&, int);
template Verdict VerdictOf(const OnlineVerifier<Pose3>&,
                           const std::vector<int>&, int);

}  // namespace rrr
