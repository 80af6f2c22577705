// RRR judged against a maintained map: the cost of a decision does not grow
// with the map.
#ifndef RRR_RRR_MAP_MAP_VERIFIER_H_
#define RRR_RRR_MAP_MAP_VERIFIER_H_

#include <memory>
#include <string>
#include <vector>

#include "rrr/graph/odometry_chain.h"
#include "rrr/rrr/chi_square.h"
#include "rrr/rrr/clustering.h"
#include "rrr/rrr/map/loop_scale_history.h"
#include "rrr/rrr/map/maintained_map.h"
#include "rrr/rrr/map/noise_scale.h"
#include "rrr/rrr/online_verifier.h"
#include "rrr/rrr/options.h"

namespace rrr {

// Counters of what the procedure did, for reports and benchmarks.
struct MapVerifierStats {
  int intra_solves = 0;             // condensed intra-cluster solves
  int quick_accepts = 0;            // accepted on the map's estimate, no solve
  int trials = 0;                   // local solves against the map
  int reversals = 0;                // accepted clusters later set aside
  int reopened = 0;                 // set-aside clusters judged again
  int optimizations = 0;            // whole-map minimizations
  int not_converged = 0;            // deciding solves stopped by the limit
  int pruned = 0;                   // accepted after dropping strained links
  int reviewed = 0;                 // split clusters tried again (step 5)
  int regrouped = 0;                // of them, refuted and judged again
  double noise_scale = 1.0;         // s of the gates at the end
  std::string noise_scale_source;   // see OnlineVerifier::noise_scale_source
  double group_noise_scale = 1.0;   // OnlineVerifier::group_noise_scale
  double a_posteriori_scale = 0.0;  // MapVerifier::APosterioriScale at the end
};

// The "map" procedure (README, "Procedures"; RRR_ALGORITHM.md terms).
// Clusters are formed in arrival order. A cluster is ready when the robot has
// moved `cluster_window` poses past its last loop, or when its later stretch
// spans kClusterSpanWindows windows (it is then closed: later loops open a
// new cluster). Ready clusters are judged one at a time, in the order of the
// pose at which they became ready, against the map of odometry and the
// clusters accepted so far:
//  1. Intra-cluster (MapIntraCluster): the links the odometry refutes on
//     their own are left out (with odometry taken as true they cannot be,
//     and in a cluster they can make the greedy drop a revisit's links
//     before their own); of the rest, links are dropped, the worst first,
//     until odometry plus them passes s·χ²(α, e·|C|), and each survivor must
//     pass s·χ²(α, e); if none is left, the links dropped before D² fell most
//     are judged alone, once (a cluster can join a revisit and a false group
//     that looks like one, and the revisit can go first). A cluster left
//     empty is rejected for good. If some links survive and at least one
//     was left out for every kSplitRatio kept, none of them refuted by the
//     odometry alone, the cluster is split: the odometry could not tell
//     which of its links agree.
//  2. Against the map: Δ, the increase of the map's minimal error when the
//     surviving links S join it, must stay below s·χ²(α, e·|S|), the
//     redundancy S adds, and every link's d²_l below s·χ²(α, e) (as in
//     step 1: a cluster's sum must not hide one link the map refutes). Both
//     are checked at the map's estimate (no solve; S's error there bounds Δ
//     from above) and then after a minimization over the junctions within
//     `map_radius` hops of S's ends, at most about `map_junctions` of them
//     (MaintainedMap::Try); S is accepted when either passes.
//  3. Otherwise, while the trial leaves S's worst link with d²_l ≥
//     s·χ²(α, e), that link is dropped and the rest is tried (at most
//     kMostPrunedLinks links): odometry alone can absorb a false link that
//     the map refutes. If the rest fits (step 2's test), it is accepted
//     without them.
//  4. Otherwise S conflicts with the map. The accepted clusters that the
//     local solve strains more than it leaves S unsatisfied (each error
//     normalized by its gate, as RRR's consistency index) are set aside one
//     by one, the most strained first (at most kMostReversalsPerConflict);
//     if S then fits the map, they stay out (reversals) and S is accepted,
//     else they are restored. A cluster that lost links to the odometry in
//     step 1 holds false loops, and its rest may be a false group's: it
//     sets aside only clusters with fewer links in all than S. Then the links
//     that the first trial left under s·χ²(α, e) are tried alone, once: a false
//     group riding in a revisit fails link by link, in more links than step 3
//     drops. If they fit, they are accepted without the others, else S is set
//     aside.
//  5. Re-opening: at each whole-map minimization, every accepted split
//     cluster is reviewed that has not been since the acceptances so far
//     (accepted clusters and re-acceptances) grew kReviewGrowth-fold (a
//     bounded share of the work: each is reviewed O(log n) times over n
//     acceptances): its survivors are tried against the map without
//     them as in step 2 (their own error at the map's minimum understates
//     the increase they bring, by the share the rest of the map absorbs).
//     If they fail, the cluster leaves the map, and its links that the
//     odometry does not refute alone are judged against the map: each
//     alone (step 2's test), then grown into a group from the one with the
//     least Δ, adding each that fits alone in order of its Δ while the
//     group still fits (dropping the worst link of a compromise, as step 1
//     does, lets two links that agree outvote the one the map holds). The
//     group is accepted, else the cluster is set aside. Then, after a
//     reversal and after each whole-map minimization (see
//     RrrOptions::optimize_every), every set-aside cluster whose error at
//     the map's estimate is under its gate is judged again,
//     every accepted cluster whose error is over it is judged again, and
//     every cluster rejected in step 1 under a scale at most half of today's
//     goes through step 1 again, and so does every cluster accepted under a
//     scale at least twice today's (it leaves the map while it is judged).
// s is RrrOptions::noise_scale or, when that is 0, `noise_margin` times the
// estimate of NoiseScaleEstimate from the loops that arrived before the pose
// at which the cluster is judged (those that SamplesNoise); with an
// estimate, no cluster is judged before kMinLoopSamples such loops have
// arrived (or Finish()). Once the clusters' estimate is in force, the two
// estimates measure two kinds of error: the loops' is of a loop against the
// odometry alone, the odometry's drift between its ends included; the
// clusters' is of the loops against the map, where the drift is taken out,
// and on odometry whose covariances understate its drift it is far tighter
// (KITTI: 0.2 against the loops' 1). So s is the larger of the two
// (GroupScaleAt) in step 1, which tests links against the odometry alone,
// and against the map for several links together: a revisit whose links
// agree with each other may close drift the map has not yet seen closed.
// One link against the map (a lone link, and each link of a cluster) has
// no other to agree with and is held to the clusters' estimate. Decisions
// depend only on the inputs and their order, not on when Update() is called, so
// running it after every pose (VerifyWithMap) gives the node's decisions.
template <class Pose>
class MapVerifier : public OnlineVerifier<Pose> {
 public:
  static constexpr int kClusterSpanWindows = 5;
  static constexpr size_t kMostReversalsPerConflict = 3;
  static constexpr int kMinLoopSamples = 30;
  // A loop samples the noise scale only if its measurement departs from the
  // odometry between its ends by less than this share of the distance
  // travelled between them (SamplesNoise).
  static constexpr double kMostPlausibleDrift = 0.5;
  // A trial whose Δ is over its gate but under kNearMissFactor times it is
  // tried again over kWideRadiusFactor times the radius, and so is the
  // map without the clusters a conflict sets aside.
  static constexpr double kNearMissFactor = 10.0;
  static constexpr int kWideRadiusFactor = 4;
  // Links a cluster may lose in step 3 before it is judged a conflict.
  static constexpr int kMostPrunedLinks = 3;
  // A cluster is split when step 1 left out at least one link for every
  // kSplitRatio it kept, none of them refuted by the odometry alone (a
  // close vote: a revisit of many links that leaves out a few is not in
  // doubt).
  static constexpr size_t kSplitRatio = 2;
  // A split cluster is reviewed again once the acceptances so far grew by
  // this factor since its last review (step 5).
  static constexpr double kReviewGrowth = 1.5;

  // Throws std::invalid_argument if `options` do not validate.
  explicit MapVerifier(const RrrOptions& options);
  ~MapVerifier() override;

  std::vector<DecisionChange> Update() override { return Judge(false); }
  std::vector<DecisionChange> Finish() override { return Judge(true); }
  // The maintained map's estimates.
  std::vector<Pose> Map() override;
  // The maintained map's estimates of `poses` alone (each costs what one
  // pose between two junctions costs, whatever the size of the map).
  std::vector<Pose> MapAt(const std::vector<int>& poses) override;
  int num_clusters() const override {
    return static_cast<int>(clustering_.clusters().size());
  }
  const MapVerifierStats& stats() const { return stats_; }
  // The noise scale s of the gates for a decision at pose index `pose`
  // (RrrOptions::noise_scale if set, else noise_margin times the estimate).
  double NoiseScaleAt(int pose) const;
  // The scale of the tests of links against the odometry alone (step 1)
  // and of several links together against the map: the larger of
  // NoiseScaleAt(pose) and noise_margin times the single loops' estimate
  // (RrrOptions::noise_scale if set).
  double GroupScaleAt(int pose) const;
  double noise_scale() const override;
  std::string noise_scale_source() const override;
  // GroupScaleAt the newest pose.
  double group_noise_scale() const override;
  // The median over the accepted clusters of their error at the map's
  // estimate per degree of freedom, Σ d²_l / (e·|S|): the a-posteriori
  // variance factor of the map at its estimate now (reports only; at each
  // minimization of the whole map the gates' estimate takes these errors
  // times the map's error over the loops'). 0 while no cluster is accepted.
  double APosterioriScale() const;

  // The whole state: the record, the clusters, the map (its estimates bit
  // for bit) and the noise-scale samples (map_verifier_state.cc).
  std::string SaveState() const override;
  bool SavedUnderSameOptions(const std::string& state) const override;
  void RestoreState(const std::string& state) override;

 private:
  enum class Status { kPending, kRejected, kAccepted, kSetAside };
  struct ClusterRecord {
    Status status = Status::kPending;
    std::vector<int> survivors;  // links kept by the intra-cluster test
    std::vector<int> left_out;   // IntraClusterOutcome::left_out
    int ready_pose = -1;         // pose index at which it became ready
    double judged_scale = 0.0;   // NoiseScaleAt of its last step 1
    int reviewed_at = 0;   // acceptances so far at its last review (step 5)
    bool refuted = false;  // some link refuted by the odometry alone
  };

  std::vector<DecisionChange> Judge(bool finish);
  // Takes the graph's new poses and loops in.
  void Catch();
  // Records again, for pose indices from `pose` on, the scale from the loops
  // that arrived by each (once per Catch that sampled loops that came late).
  void RecordScalesFrom(int pose);
  // Whether loop `loop`, solved alone with the odometry, samples the noise
  // scale: its measurement departs from the odometry between its ends by
  // less than kMostPlausibleDrift times the distance travelled between them.
  // No odometry a pose graph is built on errs by half the way it measured;
  // a loop that says so is false or joins poses the odometry cannot relate
  // (a robot standing still), and either way its error tells nothing of the
  // loops' noise. It depends on no information matrix, so a stream of such
  // loops (a front-end matching a place to the road just driven, the junk
  // of a straight drive) moves the scale neither way.
  bool SamplesNoise(int loop) const;
  // The pose index at which pending cluster `c` is judged, or -1 if not yet.
  int DecisionPose(int c, bool finish) const;
  void JudgeCluster(int c);
  // Steps 2 to 4 for a cluster that passed step 1.
  void JudgeAgainstMap(int c);
  // Tries `links` against the map within map_radius hops, and within
  // kWideRadiusFactor times that on a near miss of `gate`; links in the map
  // as if they were not (MaintainedMap::Retry).
  MapTrial TryAgainstMap(const std::vector<int>& links, double gate);
  // Step 3 for cluster `c`, whose survivors failed `trial`: while the worst
  // link's d²_l is over s·χ²(α, e), drops it and tries the rest; if the rest
  // fits, it becomes the survivors and `c` is accepted (returns true).
  bool Prune(int c, const MapTrial& failed);
  // Tries `part`, links of cluster `c`, against the map; if it fits (Fits),
  // it becomes c's survivors and `c` is accepted (`*accepted`). Returns the
  // trial.
  MapTrial TryPart(int c, const std::vector<int>& part, bool* accepted);

  // The end of step 4 for cluster `c`, whose survivors failed `failed`: tries
  // the links that `failed` left under s·χ²(α, e) alone, once; if they fit,
  // they become the survivors and `c` is accepted (returns true).
  bool AcceptFittingLinks(int c, const MapTrial& failed);
  // Whether every d²_l of `loop_chi2` is under s·χ²(α, e).
  bool EachLinkFits(const std::vector<double>& loop_chi2) const;
  // Whether `trial` solved with Δ under `gate` and every link fitting.
  bool Fits(const MapTrial& trial, double gate) const;
  // Accepts `c` with the survivors the last trial tried, which raised the
  // map's minimal error by `increase`: keeps the trial's estimate and takes
  // the increase as c's noise-scale sample.
  void AcceptTrial(int c, double increase);
  // Marks `c` accepted; adds its links to the map unless a kept trial did.
  void Accept(int c, bool add_to_map);
  void SetAside(int c);
  // Takes accepted cluster `c` out of the map and marks it set aside; its
  // noise-scale sample stays.
  void LeaveMap(int c);
  // Step 5, once.
  void Reopen();
  // Step 5's review of the accepted split clusters.
  void ReviewSplitClusters();
  // Judges the links of cluster `c` (out of the map) that step 1 did not
  // refute against the map: each alone, then a group grown from the one
  // with the least Δ by each other that fits alone, in order of its Δ, if
  // the group still fits with it. Accepts the group, else sets `c` aside.
  void RegroupAgainstMap(int c);
  // Step 5 (first the review, if a whole-map minimization called for it)
  // until the map stops calling for it (at most kMostReopenRounds).
  void ReopenWhileNeeded();
  static constexpr int kMostReopenRounds = 3;
  static constexpr double kRejudgeScaleRatio = 2.0;
  // Minimizes the whole map and takes the accepted clusters' errors there,
  // times the map's error over the loops' share of it, as their
  // noise-scale samples.
  void OptimizeMap();
  double ClusterChi2AtEstimate(int c) const;
  // Each accepted cluster's error at the map's estimate, with its dof.
  std::vector<NoiseScaleEstimate::ClusterSample> AcceptedAtEstimate() const;
  // s·χ²(α, dof) for the decision being made: GroupScaleAt for more than
  // one link's dof, NoiseScaleAt for one link's.
  double Gate(int dof) const;
  // A change of the map's error that matters to decisions: s·e, the
  // expected error of one edge.
  double Significant() const;
  // Brings the candidates of the clusters touched since the last call up to
  // date; returns the changes by candidate number.
  std::vector<DecisionChange> PublishStates();

  RrrOptions options_;
  ChiSquareQuantile chi2_;
  Clustering clustering_;
  std::vector<ClusterRecord> records_;
  std::vector<int> pending_;  // clusters not judged yet
  // Per loop: D² of the loop minimized alone with the odometry, or -1 if
  // that solve failed.
  std::vector<double> alone_chi2_;
  std::vector<int> touched_;  // clusters whose status changed
  OdometryChain<Pose> chain_;
  std::unique_ptr<MaintainedMap<Pose>> map_;
  NoiseScaleEstimate scale_;
  LoopScaleHistory loop_scales_;
  int decision_pose_ = 0;  // of the decision being made
  int accepted_since_optimize_ = 0;
  int accepted_clusters_ = 0;  // acceptances so far (with re-acceptances)
  bool reopen_needed_ = false;
  bool review_needed_ = false;  // a whole-map minimization since the review
  MapVerifierStats stats_;
};

}  // namespace rrr

#endif  // RRR_RRR_MAP_MAP_VERIFIER_H_
