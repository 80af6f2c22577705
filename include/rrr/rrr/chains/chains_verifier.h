// The map procedure over time over several odometry chains: robots of a
// fleet, or sessions of one robot, that grow side by side and are joined only
// by loop closures.
#ifndef RRR_RRR_CHAINS_CHAINS_VERIFIER_H_
#define RRR_RRR_CHAINS_CHAINS_VERIFIER_H_

#include <functional>
#include <future>
#include <memory>
#include <vector>

#include "rrr/graph/chain_spans.h"
#include "rrr/graph/pose_graph.h"
#include "rrr/rrr/chains/verify_chains.h"
#include "rrr/rrr/decision_reason.h"
#include "rrr/rrr/map/map_verifier.h"
#include "rrr/rrr/online_verifier.h"
#include "rrr/rrr/options.h"

namespace rrr {

// A pose of a graph of chains: its chain and its id in that chain.
struct ChainPose {
  int chain = 0;
  PoseId id = 0;
};

// Judges the loop candidates of several chains as they arrive. Each chain's
// own loops are judged by its own MapVerifier, exactly as if the chain were
// the whole graph. The loops between chains are judged by VerifyChains'
// rules 1–5 (JudgeChains) over the graph as it is, again at every Update()
// after which a chain's decisions, or the loops between chains, changed: so
// a join is reversed when later evidence contradicts it (a join on more
// evidence, made first, puts the chains in one map that refutes it), and a
// chain's own cluster that a joined map refutes (rule 5) is refused in
// place of the chain's decision until a later run no longer refutes it.
// The decisions of a run over a chain's own loops stand in for the chain's
// where they differ from the decisions the run started from and the chain
// has not changed those since (rule 5's refutations, and what the chain
// judged again without them decides otherwise). Until two clusters join a
// pair, its loops stay pending (nothing can confirm them yet). Finish()
// runs rules 1–5 once more and refuses them (test "apart"). After Finish()
// the decisions are those of VerifyChains on Graph().
template <class Pose>
class ChainsVerifier {
 public:
  using Information = typename Constraint<Pose>::Information;

  // With `in_background`, rules 1–5 run on a thread of their own over a
  // copy of the graph taken at an update, and their decisions are taken at
  // the first update after they end (meanwhile updates take the chains' own
  // decisions, and a change that calls for rules 1–5 again runs them once
  // the running ones end): an update then costs what the chains' own
  // decisions cost, and decisions between chains come later than without,
  // by how long rules 1–5 take. Finish() waits for them and runs them once
  // more, so its decisions are the same either way. Throws
  // std::invalid_argument if `options` do not validate.
  explicit ChainsVerifier(const RrrOptions& options,
                          bool in_background = false);
  ~ChainsVerifier();

  // Starts a new chain at pose `id` (its ids count on from there); returns
  // its index (0, 1, ... in order).
  int AddChain(PoseId id, const Pose& pose);
  // Appends a pose to chain `chain`, reached from its last by odometry `z`;
  // returns the new pose's id. Throws std::out_of_range for a chain that
  // does not exist.
  PoseId AddOdometry(int chain, const Pose& z, const Information& information);
  // Adds the candidate z ≈ x_a⁻¹ · x_b and returns its number (0, 1, ... in
  // arrival order over every chain). Inside one chain as
  // OnlineVerifier::AddLoop (it waits for a pose not there yet). Between two
  // chains it waits likewise, under the same bounds. Throws
  // DegenerateCandidate, keeping nothing, for a candidate OnlineVerifier
  // refuses, and std::out_of_range for a chain that does not exist.
  int AddLoop(ChainPose a, ChainPose b, const Pose& z,
              const Information& information);

  // Judges what became ready; returns the changed decisions.
  std::vector<DecisionChange> Update() { return Judge(Step::kUpdate); }
  // Judges everything now, as at the end of a run, and minimizes each map
  // with its accepted loops; returns the changed decisions.
  std::vector<DecisionChange> Finish() { return Judge(Step::kFinish); }
  // Update() of the chains' own decisions only: rules 1–5 wait for the next
  // Update() that calls for them, or JudgeNow(). The states after a series
  // of these and one JudgeNow() are those after the same series of Update()
  // run without the background: the states of the loops between chains and
  // of those rules 1–5 stand in for are those of their last run (for a
  // resume that replays recorded updates).
  std::vector<DecisionChange> UpdateChains() {
    return Judge(Step::kChainsOnly);
  }
  // Update(), with rules 1–5 run at once over the graph as it is (after the
  // run in the background, if any, ends).
  std::vector<DecisionChange> JudgeNow() { return Judge(Step::kJudgeNow); }

  int num_chains() const { return static_cast<int>(chains_.size()); }
  int num_candidates() const { return static_cast<int>(candidates_.size()); }
  // How many candidates are in `state` now.
  int num_in_state(LoopState state) const;
  LoopState state(int candidate) const {
    return candidates_.at(candidate).state;
  }
  DecisionReason reason(int candidate) const;
  // The candidate's cluster within its chain (-1 between chains, or while
  // it waits or is not clustered yet), whether it waits for a pose, and the
  // id in its chain of the pose as of which it was decided (-1 between
  // chains or not decided).
  int cluster_of(int candidate) const;
  bool waiting(int candidate) const;
  PoseId decided_at(int candidate) const;
  // How many times the chains gave loops already clustered other clusters
  // (OnlineVerifier::num_reclusterings; the map procedure never does).
  int num_reclusterings() const;
  // The candidate's ends as given to AddLoop.
  ChainPose from(int candidate) const { return candidates_.at(candidate).a; }
  ChainPose to(int candidate) const { return candidates_.at(candidate).b; }
  // Chain `chain`'s own verifier (its poses, odometry and own loops).
  const MapVerifier<Pose>& chain(int chain) const { return *chains_.at(chain); }

  // The map chain `chain` is in: the lowest chain joined with it (itself if
  // none), as of the last Update().
  int map_of_chain(int chain) const;
  // Chain `chain`'s frame in its map's (x_map = frame · x_chain).
  Pose frame_of_chain(int chain) const;
  // The pairs of chains with candidates between them, as last judged.
  const std::vector<ChainPair<Pose>>& pairs() const { return judged_.pairs; }
  // The poses of chain `chain` in its map's frame: its own map placed by
  // its frame; after Finish(), its map minimized with every accepted loop.
  std::vector<Pose> Map(int chain);

  // Every chain in order (ids counted on over the chains, a gap of one id
  // between two), their odometry, each chain's own loops in the order they
  // entered its graph, then the loops between chains that have both poses,
  // in arrival order. `candidate_of_loop`, if given, receives each loop's
  // candidate number.
  PoseGraph<Pose> Graph(std::vector<int>* candidate_of_loop = nullptr) const;

 private:
  struct Candidate {
    ChainPose a, b;
    int own = -1;      // candidate number in its chain's verifier, if inside
    int between = -1;  // index into between_, if between chains
    LoopState state = LoopState::kPending;
    // Inside a chain whose decision is taken from rules 1–5 where they
    // differ from the chain's own (rule 5 refuted it, or judged its chain
    // again without what it refuted).
    bool overruled = false;
    DecisionReason reason;  // between chains or overruled (else the chain's)
  };
  struct Between {
    int candidate;
    Pose measurement;
    Information information;
  };

  // Rules 1–5 over a copy of the graph: what they judge, and their verdict.
  struct Judgement {
    PoseGraph<Pose> graph;               // Graph() at the copy
    std::vector<int> candidate_of_loop;  // of graph's loops
    int first_between = 0;               // graph's first loop between chains
    std::vector<ChainAlone<Pose>> alone;
    // The chains' own states of graph's loops inside them, at the copy.
    std::vector<LoopState> own_state;
    ChainsVerdict<Pose> verdict;
  };

  enum class Step { kUpdate, kChainsOnly, kJudgeNow, kFinish };
  std::vector<DecisionChange> Judge(Step step);
  // The graph as it is and each chain's own decisions and map.
  Judgement Snapshot();
  // Sets the states of the loops between chains that `j` judged and the
  // chains' frames, and the states `j` gives the chains' own loops where
  // they differ from `j.own_state` and the chain's state is still that;
  // with `finish`, loops apart are refused.
  void Apply(Judgement j, bool finish, std::vector<DecisionChange>* changes);
  void SetState(int candidate, LoopState state,
                std::vector<DecisionChange>* changes);
  // Whether pose `id` of chain `chain` exists.
  bool Exists(const ChainPose& p) const;

  RrrOptions options_;
  bool in_background_;
  std::vector<std::unique_ptr<MapVerifier<Pose>>> chains_;
  // Per chain: fleet candidate number of each of its own candidates.
  std::vector<std::vector<int>> candidate_of_own_;
  std::vector<Candidate> candidates_;
  std::vector<Between> between_;
  bool between_changed_ = false;    // rules 1–5 must run again
  std::future<Judgement> running_;  // rules 1–5 in the background
  int num_ready_judged_ = 0;        // loops between chains it took
  ChainsVerdict<Pose> judged_;      // its last result (pairs, maps)
  std::vector<Pose> frames_;        // each chain's frame in its map's
  bool finished_ = false;           // judged_.estimates minimized
};

// Feeds the chains of `graph` (ChainSpansOf) to `verifier` as robots moving
// side by side would: one pose of each chain in turn (each a new chain of
// `verifier`, in order), each of `loops` (indices of graph.loops(); every
// loop if empty) in the round its later pose comes, in their order, and
// Update() after every `update_every` rounds (calling `on_changes` with its
// changes). Finish() is left to the caller. Returns each fed loop's
// candidate number, by loop index (-1 for a loop not fed).
template <class Pose>
std::vector<int> FeedSideBySide(
    const PoseGraph<Pose>& graph, ChainsVerifier<Pose>* verifier,
    int update_every, std::vector<int> loops = {},
    const std::function<void(const std::vector<DecisionChange>&)>& on_changes =
        nullptr);

}  // namespace rrr

#endif  // RRR_RRR_CHAINS_CHAINS_VERIFIER_H_
