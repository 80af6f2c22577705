#include "rrr/rrr/map/map_verifier.h"

#include <algorithm>
#include <stdexcept>
#include <tuple>
#include <utility>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/solver/condensed_solve.h"

namespace rrr {

template <class Pose>
MapVerifier<Pose>::MapVerifier(const RrrOptions& options)
    : OnlineVerifier<Pose>(options),
      options_(options),
      chi2_(options.alpha),
      clustering_(options.cluster_window),
      scale_(Pose::kDof) {
  const std::string problem = options.Validate();
  if (!problem.empty()) throw std::invalid_argument(problem);
}

template <class Pose>
MapVerifier<Pose>::~MapVerifier() = default;

template <class Pose>
double MapVerifier<Pose>::MapScaleAt(int pose) const {
  if (options_.noise_scale > 0.0) return options_.noise_scale;
  return options_.noise_margin * scale_.ValueAt(pose);
}

template <class Pose>
double MapVerifier<Pose>::GroupScaleAt(int pose) const {
  if (options_.noise_scale > 0.0) return options_.noise_scale;
  return options_.noise_margin *
         std::max(scale_.PriorAt(pose), scale_.ValueAt(pose));
}

template <class Pose>
std::string MapVerifier<Pose>::noise_scale_source() const {
  return options_.noise_scale > 0.0
             ? "set"
             : scale_.SourceAt(this->graph().num_poses() - 1);
}

template <class Pose>
MapVerifierStats MapVerifier<Pose>::stats() const {
  MapVerifierStats stats = stats_;
  stats.noise_scale = noise_scale();
  stats.group_noise_scale = group_noise_scale();
  stats.noise_scale_source = noise_scale_source();
  stats.a_posteriori_scale = APosterioriScale();
  return stats;
}

template <class Pose>
DecisionReason MapVerifier<Pose>::reason(int candidate) const {
  const int loop = this->loop_of(candidate);
  if (loop < 0 || loop >= static_cast<int>(reasons_.size())) return {};
  return reasons_[loop];
}

template <class Pose>
std::vector<NoiseScaleEstimate::ClusterSample>
MapVerifier<Pose>::AcceptedAtEstimate() const {
  std::vector<NoiseScaleEstimate::ClusterSample> samples;
  for (size_t c = 0; c < records_.size(); ++c) {
    const ClusterRecord& record = records_[c];
    if (record.status != Status::kAccepted) continue;
    double error = 0.0;
    for (const int loop : record.accepted) error += map_->LoopChi2(loop);
    samples.push_back(
        {static_cast<int>(c), error, static_cast<int>(record.accepted.size())});
  }
  return samples;
}

template <class Pose>
double MapVerifier<Pose>::APosterioriScale() const {
  std::vector<double> per_dof;
  for (const auto& sample : AcceptedAtEstimate()) {
    per_dof.push_back(sample.error / (Pose::kDof * sample.links));
  }
  if (per_dof.empty()) return 0.0;
  const auto middle = per_dof.begin() + per_dof.size() / 2;
  std::nth_element(per_dof.begin(), middle, per_dof.end());
  return *middle;
}

template <class Pose>
double MapVerifier<Pose>::Significant() const {
  return MapScaleAt(decision_pose_) * Pose::kDof;
}

template <class Pose>
void MapVerifier<Pose>::Catch(int until) {
  const PoseGraph<Pose>& graph = this->graph();
  const ChainOdometry<Pose>& chains = this->chains();
  if (graph.num_poses() == 0) return;
  const bool everything = until >= graph.num_poses() - 1;
  if (!map_) {
    map_ = std::make_unique<MaintainedMap<Pose>>(
        graph, chains, options_.convergence, options_.map_junctions);
  }
  while (map_->num_chains() < chains.num_chains()) {
    map_->AddChain(map_->num_chains());
  }
  const PoseId span =
      static_cast<PoseId>(kClusterSpanWindows) * options_.cluster_window;
  for (int loop = static_cast<int>(this->cluster_of_loop_.size());
       loop < static_cast<int>(graph.loops().size()); ++loop) {
    if (!everything && this->poses_at_arrival(loop) - 1 > until) break;
    const auto& e = graph.loops()[loop];
    reasons_.emplace_back();
    // The later end starts the cluster: the later pose of one chain, or
    // between chains the later to arrive. Nothing but the odometry refutes
    // a loop alone: between chains its test has no degree of freedom.
    int later = std::max(e.from, e.to);
    if (chains.chain_of(e.from) == chains.chain_of(e.to)) {
      later = chains.position(e.from) > chains.position(e.to) ? e.from : e.to;
      const CondensedErrors alone =
          SolveCondensed(graph, chains, {loop}, options_.convergence);
      alone_chi2_.push_back(alone.errors.solved ? alone.errors.total_chi2
                                                : -1.0);
      if (alone.errors.solved) {
        const Pose departure =
            chains.Relative(e.from, e.to).inverse() * e.measurement;
        scale_.AddLoopSample(
            this->poses_at_arrival(loop), alone.errors.total_chi2,
            departure.translation().norm(), chains.Travelled(e.from, e.to));
      }
    } else {
      alone_chi2_.push_back(-1.0);
    }
    const int earlier = later == e.from ? e.to : e.from;
    const std::int64_t group =
        (static_cast<std::int64_t>(chains.chain_of(later)) << 32) |
        chains.chain_of(earlier);
    const int c = clustering_.Add(loop, chains.position(later),
                                  chains.position(earlier), group);
    this->cluster_of_loop_.push_back(c);
    if (c == static_cast<int>(records_.size())) {
      records_.emplace_back();
      pending_.push_back(c);
    }
    const Cluster& cluster = clustering_.clusters()[c];
    if (cluster.start_high - cluster.start_low >= span) {
      clustering_.Close(c);
      records_[c].ready_pose = this->poses_at_arrival(loop) - 1;
    }
  }
  scale_.RecordUntil(std::min(until, graph.num_poses() - 1) + 1);
}

template <class Pose>
int MapVerifier<Pose>::DecisionPose(int c, int newest, bool finish) const {
  int pose = records_[c].ready_pose;
  if (pose < 0) {
    // `cluster_window` poses on along the chain of the later ends.
    const Cluster& cluster = clustering_.clusters()[c];
    const std::vector<int>& along = this->chains().poses(cluster.group >> 32);
    const PoseId at = cluster.start_high + options_.cluster_window;
    pose = at < static_cast<PoseId>(along.size()) ? along[at]
                                                  : this->graph().num_poses();
  }
  if (options_.noise_scale == 0.0) {
    // With an estimated scale, decisions wait for enough loops to sample it.
    const int known = scale_.FirstPoseWithEnoughLoops();
    if (known < 0) return finish ? newest : -1;
    pose = std::max(pose, known);
  }
  if (pose > newest) return finish ? newest : -1;
  return pose + options_.decision_delay <= newest || finish ? pose : -1;
}

template <class Pose>
std::vector<DecisionChange> MapVerifier<Pose>::Judge(bool finish) {
  // As if updated after every pose, each pose once the next one exists (or
  // at Finish()): the loops that came by then taken in, and the clusters
  // ready there judged. Waiting for the next pose lets the candidates of a
  // pose that come after it (on another topic) join their clusters first.
  const int newest = this->graph().num_poses() - 1;
  for (int p = judged_until_ + 1; p < newest; ++p) {
    Catch(p);
    JudgeReady(p, false);
    judged_until_ = p;
  }
  if (finish && newest >= 0) {
    Catch(newest);
    JudgeReady(newest, false);
    JudgeReady(newest, true);
    judged_until_ = newest;
    decision_pose_ = newest;
    OptimizeMap();
    Arbitrate();
    RefuseApart();
  }
  return PublishStates();
}

template <class Pose>
void MapVerifier<Pose>::JudgeReady(int newest, bool finish) {
  const auto& clusters = clustering_.clusters();
  std::vector<std::pair<int, int>> ready;  // (decision pose, cluster)
  auto still_pending = pending_.begin();
  for (const int c : pending_) {
    const int pose = DecisionPose(c, newest, finish);
    if (pose >= 0) {
      ready.emplace_back(pose, c);
    } else {
      *still_pending++ = c;
    }
  }
  pending_.erase(still_pending, pending_.end());
  std::sort(ready.begin(), ready.end(), [&](const auto& a, const auto& b) {
    return std::make_tuple(a.first, clusters[a.second].start_high, a.second) <
           std::make_tuple(b.first, clusters[b.second].start_high, b.second);
  });
  for (const auto& [pose, c] : ready) {
    clustering_.Close(c);
    decision_pose_ = pose;
    JudgeCluster(c);
    if (records_[c].status == Status::kRefused) ReviseJoin(c);
    Arbitrate();
  }
}

template <class Pose>
std::vector<Pose> MapVerifier<Pose>::Map() {
  // Only what Judge() took in: a loop taken in early would change decisions.
  Catch(judged_until_);
  if (!map_) return {};
  return map_->Estimates(options_.threads);
}

template <class Pose>
std::vector<Pose> MapVerifier<Pose>::MapAt(const std::vector<int>& poses) {
  Catch(judged_until_);
  std::vector<Pose> out;
  out.reserve(poses.size());
  for (const int p : poses) {
    if (p < 0 || p >= this->graph().num_poses()) {
      throw std::out_of_range("pose index " + std::to_string(p) +
                              " is not in the graph");
    }
    out.push_back(map_->Estimate(p));
  }
  return out;
}

template <class Pose>
std::vector<DecisionChange> MapVerifier<Pose>::PublishStates() {
  std::sort(touched_.begin(), touched_.end());
  touched_.erase(std::unique(touched_.begin(), touched_.end()), touched_.end());
  std::vector<DecisionChange> changes;
  const auto& clusters = clustering_.clusters();
  for (const int c : touched_) {
    const ClusterRecord& record = records_[c];
    for (const int loop : clusters[c].loops) {
      LoopState state = LoopState::kPending;
      if (std::binary_search(record.accepted.begin(), record.accepted.end(),
                             loop)) {
        state = LoopState::kAccepted;
      } else if (record.status != Status::kPending &&
                 reasons_[loop].test != DecisionTest::kJoin) {
        state = LoopState::kRejected;
      }
      this->SetState(this->candidate_of_loop(loop), state, &changes);
    }
  }
  touched_.clear();
  std::sort(changes.begin(), changes.end(),
            [](const DecisionChange& a, const DecisionChange& b) {
              return a.candidate < b.candidate;
            });
  return changes;
}

template <class Pose>
void MapVerifier<Pose>::Record(const std::vector<int>& links, DecisionTest test,
                               double statistic, int free_frames) {
  if (links.empty()) return;
  const bool own = test == DecisionTest::kAlone ||
                   test == DecisionTest::kOwnLink ||
                   test == DecisionTest::kOwn || test == DecisionTest::kJoin;
  const Against against = own ? Against::kOdometry : Against::kMap;
  const size_t checked = links.size() - free_frames;
  DecisionReason reason;
  reason.test = test;
  reason.statistic = statistic;
  reason.dof = Pose::kDof * static_cast<int>(checked);
  // No degree of freedom (one link between maps apart): no gate.
  reason.gate = checked > 0 ? Gate(against, checked) : 0.0;
  reason.scale = checked > 0 ? reason.gate / chi2_(reason.dof)
                             : Gate(against, 1) / chi2_(Pose::kDof);
  reason.pose = decision_pose_;
  for (const int loop : links) reasons_[loop] = reason;
}

template <class Pose>
void MapVerifier<Pose>::Accept(int c, const std::vector<int>& links,
                               double statistic, bool from_trial) {
  ClusterRecord& record = records_[c];
  if (from_trial) {
    map_->KeepTrial(Significant());
  } else {
    map_->Add(links, options_.map_radius, Significant());
  }
  record.status = Status::kAccepted;
  record.accepted = links;
  Forget(c);
  std::sort(record.accepted.begin(), record.accepted.end());
  Record(links, DecisionTest::kMap, statistic);
  scale_.SetClusterSample(c, statistic, static_cast<int>(links.size()));
  touched_.push_back(c);
  ++accepted_clusters_;
  if (++accepted_since_optimize_ >=
      std::max<double>(options_.optimize_every,
                       options_.optimize_growth * accepted_clusters_)) {
    OptimizeMap();
  }
}

template <class Pose>
void MapVerifier<Pose>::LeaveMap(int c) {
  map_->Remove(records_[c].accepted, options_.map_radius, Significant());
  scale_.RemoveClusterSample(c);
  records_[c].accepted.clear();
  records_[c].status = Status::kRefused;
  touched_.push_back(c);
}

template <class Pose>
void MapVerifier<Pose>::OptimizeMap() {
  if (!map_) return;
  ++stats_.optimizations;
  this->CountSolves(1);
  const MinimizeResult result = map_->Optimize();
  if (!result.converged) ++stats_.not_converged;
  // At the whole map's minimum the accepted clusters' errors give the
  // a-posteriori scale, which their trials' increases overstate.
  scale_.SetClusterSamplesAtMinimum(AcceptedAtEstimate(), result.final_chi2);
  accepted_since_optimize_ = 0;
  arbiter_due_ = true;
}

template class MapVerifier<Pose2>;
template class MapVerifier<Pose3>;

}  // namespace rrr
