#include "rrr/rrr/chains/chains_verifier.h"

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <string>
#include <utility>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/graph/candidate_defect.h"
#include "rrr/solver/chain_maps.h"

namespace rrr {

template <class Pose>
ChainsVerifier<Pose>::ChainsVerifier(const RrrOptions& options,
                                     bool in_background)
    : options_(options), in_background_(in_background) {
  const std::string problem = options.Validate();
  if (!problem.empty()) throw std::invalid_argument(problem);
}

template <class Pose>
ChainsVerifier<Pose>::~ChainsVerifier() = default;

template <class Pose>
int ChainsVerifier<Pose>::AddChain(PoseId id, const Pose& pose) {
  chains_.push_back(std::make_unique<MapVerifier<Pose>>(options_));
  chains_.back()->AddFirstPose(id, pose);
  candidate_of_own_.emplace_back();
  finished_ = false;
  return num_chains() - 1;
}

template <class Pose>
PoseId ChainsVerifier<Pose>::AddOdometry(int chain, const Pose& z,
                                         const Information& information) {
  finished_ = false;
  return chains_.at(chain)->AddOdometry(z, information);
}

template <class Pose>
bool ChainsVerifier<Pose>::Exists(const ChainPose& p) const {
  return chains_.at(p.chain)->graph().IndexOf(p.id) >= 0;
}

template <class Pose>
int ChainsVerifier<Pose>::AddLoop(ChainPose a, ChainPose b, const Pose& z,
                                  const Information& information) {
  static_cast<void>(chains_.at(a.chain));
  static_cast<void>(chains_.at(b.chain));
  Candidate candidate;
  candidate.a = a;
  candidate.b = b;
  if (a.chain == b.chain) {
    candidate.own = chains_[a.chain]->AddLoop(a.id, b.id, z, information);
    candidate_of_own_[a.chain].push_back(num_candidates());
  } else {
    const auto name = [](const ChainPose& p) {
      return std::to_string(p.chain) + ":" + std::to_string(p.id);
    };
    const std::string pair = "candidate " + name(a) + " -> " + name(b);
    int waiting = 0;
    for (const Between& other : between_) {
      const Candidate& c = candidates_[other.candidate];
      waiting += !Exists(c.a) || !Exists(c.b);
      if (c.a.chain == a.chain && c.a.id == a.id && c.b.chain == b.chain &&
          c.b.id == b.id && other.measurement.Log() == z.Log() &&
          other.information == information) {
        throw DegenerateCandidate(
            CandidateDefect::kDuplicate,
            pair + " repeats candidate " + std::to_string(other.candidate));
      }
    }
    for (const ChainPose& p : {a, b}) {
      const auto& ids = chains_[p.chain]->graph().ids();
      if (p.id < ids.front()) {
        throw DegenerateCandidate(CandidateDefect::kUnknownPose,
                                  pair + ": pose " + name(p) +
                                      " precedes its chain's first pose " +
                                      std::to_string(ids.front()));
      }
      if (p.id > ids.back() + options_.max_future_poses) {
        throw DegenerateCandidate(
            CandidateDefect::kTooFarAhead,
            pair + ": pose " + name(p) + " is more than " +
                std::to_string(options_.max_future_poses) +
                " poses past its chain's newest, " +
                std::to_string(ids.back()));
      }
    }
    if ((!Exists(a) || !Exists(b)) && waiting >= options_.max_waiting) {
      throw DegenerateCandidate(CandidateDefect::kWaitingFull,
                                pair + " would wait while " +
                                    std::to_string(options_.max_waiting) +
                                    " candidates between chains already wait");
    }
    candidate.between = static_cast<int>(between_.size());
    between_.push_back({num_candidates(), z, information});
    between_changed_ = true;
  }
  candidates_.push_back(candidate);
  finished_ = false;
  return num_candidates() - 1;
}

template <class Pose>
int ChainsVerifier<Pose>::num_in_state(LoopState state) const {
  return static_cast<int>(
      std::count_if(candidates_.begin(), candidates_.end(),
                    [&](const Candidate& c) { return c.state == state; }));
}

template <class Pose>
DecisionReason ChainsVerifier<Pose>::reason(int candidate) const {
  const Candidate& c = candidates_.at(candidate);
  return c.own >= 0 && !c.overruled ? chains_[c.a.chain]->reason(c.own)
                                    : c.reason;
}

template <class Pose>
int ChainsVerifier<Pose>::cluster_of(int candidate) const {
  const Candidate& c = candidates_.at(candidate);
  return c.own >= 0 ? chains_[c.a.chain]->cluster_of(c.own) : -1;
}

template <class Pose>
bool ChainsVerifier<Pose>::waiting(int candidate) const {
  const Candidate& c = candidates_.at(candidate);
  return c.own >= 0 ? chains_[c.a.chain]->loop_of(c.own) < 0
                    : !Exists(c.a) || !Exists(c.b);
}

template <class Pose>
int ChainsVerifier<Pose>::num_reclusterings() const {
  int n = 0;
  for (const auto& chain : chains_) n += chain->num_reclusterings();
  return n;
}

template <class Pose>
PoseId ChainsVerifier<Pose>::decided_at(int candidate) const {
  const Candidate& c = candidates_.at(candidate);
  if (c.own < 0) return -1;
  const int pose = chains_[c.a.chain]->reason(c.own).pose;
  return pose < 0 ? -1 : chains_[c.a.chain]->graph().ids()[pose];
}

template <class Pose>
int ChainsVerifier<Pose>::map_of_chain(int chain) const {
  static_cast<void>(chains_.at(chain));
  return chain < static_cast<int>(judged_.map_of_chain.size())
             ? judged_.map_of_chain[chain]
             : chain;
}

template <class Pose>
Pose ChainsVerifier<Pose>::frame_of_chain(int chain) const {
  static_cast<void>(chains_.at(chain));
  return chain < static_cast<int>(frames_.size()) ? frames_[chain] : Pose();
}

template <class Pose>
std::vector<Pose> ChainsVerifier<Pose>::Map(int chain) {
  if (finished_) {
    const ChainSpan& span = judged_.chains.at(chain);
    return std::vector<Pose>(judged_.estimates.begin() + span.first,
                             judged_.estimates.begin() + span.last + 1);
  }
  std::vector<Pose> map = chains_.at(chain)->Map();
  const Pose frame = frame_of_chain(chain);
  for (Pose& x : map) x = frame * x;
  return map;
}

template <class Pose>
PoseGraph<Pose> ChainsVerifier<Pose>::Graph(
    std::vector<int>* candidate_of_loop) const {
  PoseGraph<Pose> graph;
  std::vector<int> candidates;
  std::vector<int> offset(chains_.size());
  PoseId id = 0;
  for (size_t c = 0; c < chains_.size(); ++c) {
    const PoseGraph<Pose>& own = chains_[c]->graph();
    offset[c] = graph.num_poses();
    for (const Pose& x : own.estimates()) graph.AddPose(id++, x);
    ++id;  // a gap: no odometry to the next chain
    for (auto e : own.odometry()) {
      e.from += offset[c];
      e.to += offset[c];
      graph.AddEdge(e);
    }
    std::vector<int> own_of_loop(own.loops().size());
    for (int k = 0; k < chains_[c]->num_candidates(); ++k) {
      if (chains_[c]->loop_of(k) >= 0) own_of_loop[chains_[c]->loop_of(k)] = k;
    }
    for (size_t k = 0; k < own.loops().size(); ++k) {
      auto e = own.loops()[k];
      e.from += offset[c];
      e.to += offset[c];
      graph.AddEdge(e);
      candidates.push_back(candidate_of_own_[c][own_of_loop[k]]);
    }
  }
  for (const Between& b : between_) {
    const Candidate& c = candidates_[b.candidate];
    if (!Exists(c.a) || !Exists(c.b)) continue;
    Constraint<Pose> e;
    e.from = offset[c.a.chain] + chains_[c.a.chain]->graph().IndexOf(c.a.id);
    e.to = offset[c.b.chain] + chains_[c.b.chain]->graph().IndexOf(c.b.id);
    e.measurement = b.measurement;
    e.information = b.information;
    graph.AddEdge(e);
    candidates.push_back(b.candidate);
  }
  if (candidate_of_loop) *candidate_of_loop = std::move(candidates);
  return graph;
}

template <class Pose>
void ChainsVerifier<Pose>::SetState(int candidate, LoopState state,
                                    std::vector<DecisionChange>* changes) {
  Candidate& c = candidates_[candidate];
  if (c.state == state) return;
  changes->push_back({candidate, c.state, state});
  c.state = state;
}

template <class Pose>
std::vector<DecisionChange> ChainsVerifier<Pose>::Judge(Step step) {
  const bool finish = step == Step::kFinish;
  std::vector<DecisionChange> changes;
  if (chains_.empty()) return changes;
  for (int c = 0; c < num_chains(); ++c) {
    MapVerifier<Pose>& chain = *chains_[c];
    for (const DecisionChange& change :
         finish ? chain.Finish() : chain.Update()) {
      const int candidate = candidate_of_own_[c][change.candidate];
      if (!candidates_[candidate].overruled) {
        SetState(candidate, change.current, &changes);
      }
      between_changed_ = between_changed_ || !between_.empty();
    }
  }
  // A loop between chains whose pose arrived takes part from now on.
  int ready = 0;
  for (const Between& b : between_) {
    const Candidate& c = candidates_[b.candidate];
    ready += Exists(c.a) && Exists(c.b);
  }
  if (ready != num_ready_judged_) between_changed_ = true;
  num_ready_judged_ = ready;
  if (step == Step::kChainsOnly) return changes;
  // Rules 1–5 that ran in the background: their decisions now (judged again
  // at once at Finish() and JudgeNow()).
  const bool now = finish || step == Step::kJudgeNow;
  if (running_.valid() && (now || running_.wait_for(std::chrono::seconds(0)) ==
                                      std::future_status::ready)) {
    Judgement done = running_.get();
    if (!now) Apply(std::move(done), false, &changes);
  }
  if (now) {
    Judgement j = Snapshot();
    j.verdict = JudgeChains(j.graph, j.alone, options_);
    Apply(std::move(j), finish, &changes);
    between_changed_ = false;
  } else if (between_changed_ && !running_.valid()) {
    between_changed_ = false;
    Judgement j = Snapshot();
    if (in_background_) {
      running_ = std::async(
          std::launch::async, [j = std::move(j), options = options_]() mutable {
            j.verdict = JudgeChains(j.graph, j.alone, options);
            return std::move(j);
          });
    } else {
      j.verdict = JudgeChains(j.graph, j.alone, options_);
      Apply(std::move(j), false, &changes);
    }
  }
  finished_ = finish;
  return changes;
}

template <class Pose>
typename ChainsVerifier<Pose>::Judgement ChainsVerifier<Pose>::Snapshot() {
  Judgement j;
  j.graph = Graph(&j.candidate_of_loop);
  j.alone.resize(chains_.size());
  for (size_t c = 0; c < chains_.size(); ++c) {
    MapVerifier<Pose>* chain = chains_[c].get();
    const int num_loops = static_cast<int>(chain->graph().loops().size());
    std::vector<int> loop_of_candidate(chain->num_candidates());
    for (int k = 0; k < chain->num_candidates(); ++k) {
      loop_of_candidate[k] = chain->loop_of(k);
    }
    j.alone[c].verdict = VerdictOf(*chain, loop_of_candidate, num_loops);
    j.alone[c].map = chain->Map();
    j.alone[c].stats = chain->stats();
    for (int k = 0; k < num_loops; ++k) {
      j.alone[c].inside.push_back(j.first_between++);
    }
  }
  for (int k = 0; k < j.first_between; ++k) {
    const Candidate& c = candidates_[j.candidate_of_loop[k]];
    j.own_state.push_back(chains_[c.a.chain]->state(c.own));
  }
  return j;
}

template <class Pose>
void ChainsVerifier<Pose>::Apply(Judgement j, bool finish,
                                 std::vector<DecisionChange>* changes) {
  ChainsVerdict<Pose>& judged = j.verdict;
  std::vector<bool> accepted(j.graph.loops().size(), false);
  for (const int k : judged.verdict.accepted) accepted[k] = true;
  for (int k = 0; k < j.first_between; ++k) {
    Candidate& c = candidates_[j.candidate_of_loop[k]];
    const LoopState own = chains_[c.a.chain]->state(c.own);
    // Rules 1–5 stand in for the chain's decision where they decided
    // otherwise than the decision `j` copied, while the chain has not
    // changed it since (a newer decision stands until they run again); a
    // loop the chain had not decided yet waits for the chain.
    const LoopState then = j.own_state[k];
    c.overruled = judged.verdict.reasons[k].test == DecisionTest::kJoinedMap ||
                  (then != LoopState::kPending && own == then &&
                   accepted[k] != (then == LoopState::kAccepted));
    if (c.overruled) c.reason = judged.verdict.reasons[k];
    SetState(j.candidate_of_loop[k],
             c.overruled
                 ? (accepted[k] ? LoopState::kAccepted : LoopState::kRejected)
                 : own,
             changes);
  }
  for (size_t k = j.first_between; k < j.graph.loops().size(); ++k) {
    Candidate& c = candidates_[j.candidate_of_loop[k]];
    c.reason = judged.verdict.reasons[k];
    const bool waits = !finish && c.reason.test == DecisionTest::kApart;
    SetState(j.candidate_of_loop[k],
             accepted[k] ? LoopState::kAccepted
                         : (waits ? LoopState::kPending : LoopState::kRejected),
             changes);
  }
  const int chains = static_cast<int>(judged.chains.size());
  frames_.assign(chains, Pose());
  for (int m = 0; m < chains; ++m) {
    const std::vector<Pose> frames = FramesIn(judged.pairs, chains, m);
    for (int c = 0; c < chains; ++c) {
      if (judged.map_of_chain[c] == m) frames_[c] = frames[c];
    }
  }
  judged_ = std::move(judged);
}

template <class Pose>
std::vector<int> FeedSideBySide(
    const PoseGraph<Pose>& graph, ChainsVerifier<Pose>* verifier,
    int update_every, std::vector<int> loops,
    const std::function<void(const std::vector<DecisionChange>&)>& on_changes) {
  const std::vector<ChainSpan> spans = ChainSpansOf(graph);
  const std::vector<OdometryChain<Pose>> odometry = OdometryOf(graph, spans);
  const int first_chain = verifier->num_chains();
  if (loops.empty()) {
    for (size_t k = 0; k < graph.loops().size(); ++k) {
      loops.push_back(static_cast<int>(k));
    }
  }
  // A pose of `graph` as a pose of its chain, in the rounds counted in it.
  const auto at = [&](int p) {
    const int c = ChainHolding(spans, p);
    return std::pair(ChainPose{first_chain + c, graph.ids()[p]},
                     p - spans[c].first);
  };
  std::vector<std::pair<int, int>> by_round;  // (round, loop)
  for (const int k : loops) {
    const auto& e = graph.loops()[k];
    by_round.emplace_back(std::max(at(e.from).second, at(e.to).second), k);
  }
  std::stable_sort(
      by_round.begin(), by_round.end(),
      [](const auto& x, const auto& y) { return x.first < y.first; });
  std::vector<int> candidate_of_loop(graph.loops().size(), -1);
  size_t next = 0;
  int longest = 0;
  for (const ChainSpan& span : spans) longest = std::max(longest, span.size());
  for (int round = 0; round < longest; ++round) {
    for (size_t c = 0; c < spans.size(); ++c) {
      const int p = spans[c].first + round;
      if (p > spans[c].last) continue;
      if (round == 0) {
        verifier->AddChain(graph.ids()[p], graph.estimates()[p]);
      } else {
        const Constraint<Pose> step = odometry[c].Between(round - 1, round);
        verifier->AddOdometry(first_chain + static_cast<int>(c),
                              step.measurement, step.information);
      }
    }
    for (; next < by_round.size() && by_round[next].first == round; ++next) {
      const auto& e = graph.loops()[by_round[next].second];
      candidate_of_loop[by_round[next].second] = verifier->AddLoop(
          at(e.from).first, at(e.to).first, e.measurement, e.information);
    }
    if ((round + 1) % update_every == 0) {
      const std::vector<DecisionChange> changes = verifier->Update();
      if (on_changes) on_changes(changes);
    }
  }
  return candidate_of_loop;
}

template class ChainsVerifier<Pose2>;
template class ChainsVerifier<Pose3>;
template std::vector<int> FeedSideBySide(
    const PoseGraph<Pose2>&, ChainsVerifier<Pose2>*, int, std::vector<int>,
    const std::function<void(const std::vector<DecisionChange>&)>&);
template std::vector<int> FeedSideBySide(
    const PoseGraph<Pose3>&, ChainsVerifier<Pose3>*, int, std::vector<int>,
    const std::function<void(const std::vector<DecisionChange>&)>&);

}  // namespace rrr
