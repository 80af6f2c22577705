// RRR over time: the poses, odometry and loop candidates a verifier is given
// as the robot moves, and the state of every candidate.
#ifndef RRR_RRR_ONLINE_VERIFIER_H_
#define RRR_RRR_ONLINE_VERIFIER_H_

#include <algorithm>
#include <array>
#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "rrr/graph/candidate_defect.h"
#include "rrr/graph/chain_odometry.h"
#include "rrr/graph/pose_graph.h"
#include "rrr/io/byte_stream.h"
#include "rrr/rrr/decision_reason.h"
#include "rrr/rrr/options.h"
#include "rrr/rrr/verdict.h"

namespace rrr {

enum class LoopState { kPending, kAccepted, kRejected };
const char* ToString(LoopState state);

// A candidate whose state changed in an update.
struct DecisionChange {
  int candidate;  // candidate number, in arrival order
  LoopState previous;
  LoopState current;
};

// The interface of a verifier that judges loop candidates as they arrive
// (RRR_ALGORITHM.md §4), and the record it keeps: the pose graph built from
// the inputs, the candidates in arrival order, those waiting for a pose, and
// each candidate's state. Subclasses decide (Update, Finish) and report the
// map of odometry and accepted loops (Map).
template <class Pose>
class OnlineVerifier {
 public:
  using Information = typename Constraint<Pose>::Information;

  // `bounds` (RrrOptions::max_future_poses and max_waiting) limit what may
  // wait for a pose.
  explicit OnlineVerifier(const RrrOptions& bounds);
  virtual ~OnlineVerifier() = default;

  // Makes room for `poses` poses and `loops` candidates in all, so that
  // adding them moves nothing already added; decides nothing.
  void Reserve(int poses, int loops) {
    graph_.Reserve(poses, std::max(poses - 1, 0) + loops);
  }
  // Starts the chain at pose `id`. Throws std::logic_error if it has started.
  void AddFirstPose(PoseId id, const Pose& pose);
  // Starts a new odometry chain (a robot, or a session of one) at pose `id`
  // with estimate `pose`; returns its index (0, 1, ... in order). Its ids
  // count on from `id`, so chains that grow side by side need first ids far
  // apart (a robot's letter in the top byte, as GTSAM's Symbol keys).
  // Throws std::invalid_argument if `id` is a pose already, and
  // std::logic_error for a second chain if the procedure judges one
  // (JudgesSeveralChains).
  int AddChain(PoseId id, const Pose& pose);
  // Appends to chain `chain` the pose with its next id (last id + 1),
  // reached from its last pose by odometry `z`; returns the new pose's id.
  // Throws std::out_of_range for a chain that does not exist, and
  // std::logic_error if that id is another chain's pose.
  PoseId AddOdometry(int chain, const Pose& z, const Information& information);
  // AddOdometry of the newest chain. Throws std::logic_error before the
  // first pose.
  PoseId AddOdometry(const Pose& z, const Information& information);
  // Adds the candidate z ≈ x_a⁻¹ · x_b and returns its number (0, 1, ... in
  // arrival order). If a pose does not exist yet, the candidate waits for it
  // and enters the graph when it arrives. Throws DegenerateCandidate (and
  // keeps nothing) for a self loop, consecutive ids, a pose before the first
  // chain's first (it can never exist), the same pair, measurement and
  // information as an earlier candidate, a pose more than
  // `bounds.max_future_poses` ids past the newest of the chain whose ids it
  // falls among, or a candidate that would wait while `bounds.max_waiting`
  // already do (RrrOptions).
  int AddLoop(PoseId a, PoseId b, const Pose& z,
              const Information& information);

  // Judges what became ready; returns the changed decisions.
  virtual std::vector<DecisionChange> Update() = 0;
  // Judges everything now, as at the end of a run; returns the changes.
  virtual std::vector<DecisionChange> Finish() = 0;
  // The estimate of every pose of graph() with odometry and the accepted
  // loops, optimized. Reading the map changes no decision: they depend on
  // the inputs and the calls of Update() and Finish() alone.
  virtual std::vector<Pose> Map() = 0;
  // The estimates of `poses` (pose indices of graph()) in Map(). By default
  // Map() picked; a verifier may answer without computing the other poses.
  virtual std::vector<Pose> MapAt(const std::vector<int>& poses);
  virtual int num_clusters() const = 0;
  // The noise scale s the gates use now (1: the information matrices as
  // given), and where it comes from ("given", "set", "loops", "clusters").
  virtual double noise_scale() const { return 1.0; }
  virtual std::string noise_scale_source() const { return "given"; }
  // The scale of the tests whose error holds the odometry's drift, where a
  // procedure keeps one apart (MapVerifier::GroupScaleAt); noise_scale()
  // where it does not.
  virtual double group_noise_scale() const { return noise_scale(); }
  // Why candidate `candidate` is in its state (DecisionTest::kNotJudged
  // while pending, or where the procedure records no reasons).
  virtual DecisionReason reason(int candidate) const {
    static_cast<void>(candidate);
    return {};
  }
  // The candidate's cluster, or -1 while it waits for a pose or is not
  // clustered yet.
  int cluster_of(int candidate) const;
  // How many times loops already clustered were given other clusters (the
  // published procedure clusters every loop again, in batch order, as loops
  // arrive; the map procedure never does).
  int num_reclusterings() const { return num_reclusterings_; }

  // Whether the procedure judges several odometry chains.
  virtual bool JudgesSeveralChains() const { return false; }
  // The map chain `chain` is in: the lowest chain joined with it by the
  // accepted loops (itself if none; one chain is its own map).
  virtual int MapOfChain(int chain) const { return chain; }

  // The poses, odometry and candidates given, in arrival order: the chains'
  // poses interleave as they came.
  const PoseGraph<Pose>& graph() const { return graph_; }
  // The chains of graph() and their odometry.
  const ChainOdometry<Pose>& chains() const { return chains_; }
  int num_chains() const { return chains_.num_chains(); }
  int num_candidates() const { return static_cast<int>(candidates_.size()); }
  // Candidates waiting for a pose that does not exist yet.
  int num_waiting() const { return static_cast<int>(waiting_.size()); }
  LoopState state(int candidate) const {
    return candidates_.at(candidate).state;
  }
  // How many candidates are in `state` now (kept as states change).
  int num_in_state(LoopState state) const {
    return count_by_state_[static_cast<int>(state)];
  }
  // The candidate's loop index in graph().loops(), or -1 while it waits.
  int loop_of(int candidate) const { return candidates_.at(candidate).loop; }
  // Whether the candidate waits for a pose that does not exist yet.
  bool waiting(int candidate) const { return loop_of(candidate) < 0; }
  // The candidate's end ids as given to AddLoop.
  std::pair<PoseId, PoseId> ends_of(int candidate) const;
  // Loop indices of the accepted candidates, ascending.
  std::vector<int> AcceptedLoops() const;
  // Number of consistency solves run so far.
  int num_solves() const { return num_solves_; }

  // The verifier's state after its last Update() or Finish(), as bytes that
  // RestoreState reads back, or "" if this verifier does not save its state
  // (a session is then resumed by running every update again).
  virtual std::string SaveState() const { return {}; }
  // Whether `state` was saved by a verifier of this kind under the same
  // options, so that RestoreState takes it. Throws std::runtime_error if
  // `state` is not a saved state of this kind of verifier.
  virtual bool SavedUnderSameOptions(const std::string& state) const;
  // For a new verifier with the same options, given the same inputs (in the
  // same order) as the one that saved `state` had been given when it saved
  // it, and no Update() since: restores that state, so that it goes on to
  // decide exactly as that one would have. Throws std::runtime_error naming
  // the problem if `state` is not a state of such a verifier (the verifier
  // must then be discarded), and std::logic_error if this verifier does not
  // restore states (SaveState gives "").
  virtual void RestoreState(const std::string& state);

 protected:
  // The candidate of graph loop `loop`.
  int candidate_of_loop(int loop) const { return candidate_of_loop_[loop]; }
  // The number of poses the graph had when loop `loop` entered it, or had
  // when its later pose arrived if the loop came after that (so that a loop
  // that comes late counts as if it had come in time).
  int poses_at_arrival(int loop) const { return poses_at_arrival_[loop]; }
  // Sets every candidate's state to `next` (by candidate number) and returns
  // the changes.
  std::vector<DecisionChange> SetStates(const std::vector<LoopState>& next);
  // Sets one candidate's state, recording a change in `changes`.
  void SetState(int candidate, LoopState state,
                std::vector<DecisionChange>* changes);
  void CountSolves(int solves) { num_solves_ += solves; }
  // The cluster of each graph loop clustered so far; subclasses keep it,
  // and call CountReclustering when they change an entry they had set.
  std::vector<int> cluster_of_loop_;
  void CountReclustering() { ++num_reclusterings_; }
  // The part of SaveState and RestoreState this class keeps: the inputs'
  // counts (checked on restoring), every candidate's state, the counters and
  // cluster_of_loop_.
  void SaveRecord(ByteWriter* out) const;
  void RestoreRecord(ByteReader* in);

 private:
  struct Candidate {
    PoseId a, b;
    Pose measurement;
    Information information;
    int loop = -1;
    LoopState state = LoopState::kPending;
  };
  // Moves the candidates whose poses exist into the graph.
  void ApplyWaiting();

  int max_future_poses_, max_waiting_;
  PoseGraph<Pose> graph_;
  ChainOdometry<Pose> chains_;
  std::map<PoseId, int> chain_of_first_id_;
  std::vector<Candidate> candidates_;
  std::array<int, 3> count_by_state_{};  // by LoopState
  std::vector<int> waiting_;             // candidate numbers
  // Candidate numbers by their pair of end ids, to find duplicates.
  std::map<std::pair<PoseId, PoseId>, std::vector<int>> by_pair_;
  std::vector<int> candidate_of_loop_;  // graph loop index -> candidate
  std::vector<int> poses_at_arrival_;   // graph loop index -> poses
  int num_solves_ = 0;
  int num_reclusterings_ = 0;
};

// The order in which the poses of `graph` arrive: the graph's order (its
// chains one after another, as the sessions of one robot), or with
// `side_by_side` as robots that move at once: each pose at its robot's time,
// its index below the robot's letter where ids are GTSAM symbols (AsSymbol:
// a robot's sessions come one after another), else its place in its chain
// (ChainSpansOf); poses of the same time in chain order.
template <class Pose>
std::vector<int> ArrivalOrder(const PoseGraph<Pose>& graph, bool side_by_side);

// Feeds `graph` to `verifier` as robots would produce it: pose after pose in
// `order` (ArrivalOrder; the graph's order if empty; a part of an order feeds
// those poses alone), each the first of a new chain where it has no odometry
// to its predecessor (ChainSpansOf) or else reached by its odometry, each
// loop candidate right after its later pose, or with `loop_lag` > 0 as from
// a loop topic that lags by up to that many poses (loop k comes
// k mod (loop_lag + 1) poses late, at the last pose at the latest), Update()
// after every `update_every` poses, then Finish() if `finish`. Calls
// `on_changes` with the changes of each update if given. Returns the graph
// loop index of each candidate number.
template <class Pose>
std::vector<int> FeedInArrivalOrder(
    const PoseGraph<Pose>& graph, OnlineVerifier<Pose>* verifier,
    int update_every = 1,
    const std::function<void(const std::vector<DecisionChange>&)>& on_changes =
        nullptr,
    int loop_lag = 0, const std::vector<int>& order = {}, bool finish = true);

// The decisions of `verifier` as a verdict over `num_loops` loops, its
// candidate c being loop loop_of_candidate[c] (-1: none); a loop that is no
// candidate is in neither list.
template <class Pose>
Verdict VerdictOf(const OnlineVerifier<Pose>& verifier,
                  const std::vector<int>& loop_of_candidate, int num_loops);

}  // namespace rrr

#endif  // RRR_RRR_ONLINE_VERIFIER_H_
