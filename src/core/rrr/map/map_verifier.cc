#include "rrr/rrr/map/map_verifier.h"

#include <algorithm>
#include <iterator>
#include <numeric>
#include <stdexcept>
#include <tuple>
#include <utility>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/rrr/map/cluster_strain.h"
#include "rrr/rrr/map/map_intra_cluster.h"
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
double MapVerifier<Pose>::NoiseScaleAt(int pose) const {
  if (options_.noise_scale > 0.0) return options_.noise_scale;
  return options_.noise_margin * scale_.Value(loop_scales_.At(pose));
}

template <class Pose>
double MapVerifier<Pose>::GroupScaleAt(int pose) const {
  const double of_the_map = NoiseScaleAt(pose);
  if (options_.noise_scale > 0.0) return of_the_map;
  return std::max(of_the_map, options_.noise_margin * loop_scales_.At(pose));
}

template <class Pose>
double MapVerifier<Pose>::noise_scale() const {
  return NoiseScaleAt(this->graph().num_poses() - 1);
}

template <class Pose>
double MapVerifier<Pose>::group_noise_scale() const {
  return GroupScaleAt(this->graph().num_poses() - 1);
}

template <class Pose>
std::string MapVerifier<Pose>::noise_scale_source() const {
  return options_.noise_scale > 0.0 ? "set" : scale_.Source();
}

template <class Pose>
std::vector<NoiseScaleEstimate::ClusterSample>
MapVerifier<Pose>::AcceptedAtEstimate() const {
  std::vector<NoiseScaleEstimate::ClusterSample> samples;
  for (size_t c = 0; c < records_.size(); ++c) {
    if (records_[c].status != Status::kAccepted) continue;
    samples.push_back(
        {static_cast<int>(c), ClusterChi2AtEstimate(static_cast<int>(c)),
         Pose::kDof * static_cast<int>(records_[c].survivors.size())});
  }
  return samples;
}

template <class Pose>
double MapVerifier<Pose>::APosterioriScale() const {
  std::vector<double> per_dof;
  for (const auto& sample : AcceptedAtEstimate()) {
    per_dof.push_back(sample.error / sample.dof);
  }
  if (per_dof.empty()) return 0.0;
  const auto middle = per_dof.begin() + per_dof.size() / 2;
  std::nth_element(per_dof.begin(), middle, per_dof.end());
  return *middle;
}

template <class Pose>
double MapVerifier<Pose>::Significant() const {
  return NoiseScaleAt(decision_pose_) * Pose::kDof;
}

template <class Pose>
double MapVerifier<Pose>::Gate(int dof) const {
  const double scale = dof > Pose::kDof ? GroupScaleAt(decision_pose_)
                                        : NoiseScaleAt(decision_pose_);
  return scale * chi2_(dof);
}

template <class Pose>
void MapVerifier<Pose>::Catch() {
  const PoseGraph<Pose>& graph = this->graph();
  if (graph.num_poses() == 0) return;
  if (!map_) {
    map_ = std::make_unique<MaintainedMap<Pose>>(
        graph, chain_, options_.convergence, options_.map_junctions);
  }
  // The verifier's graph has one forward odometry edge per pose, in order.
  for (int k = chain_.num_poses(); k < graph.num_poses(); ++k) {
    const auto& e = graph.odometry()[k - 1];
    chain_.Append(e.measurement, e.information);
  }
  // The scale before pose p counts the loops that arrived with fewer than
  // p + 1 poses.
  const auto record_until = [&](int poses) {
    loop_scales_.ExtendTo(poses, scale_.FromLoops(), scale_.num_loop_samples());
  };
  const PoseId span =
      static_cast<PoseId>(kClusterSpanWindows) * options_.cluster_window;
  int earliest_late = graph.num_poses();  // arrival of a loop that came late
  for (int loop = static_cast<int>(this->cluster_of_loop_.size());
       loop < static_cast<int>(graph.loops().size()); ++loop) {
    const int arrival = this->poses_at_arrival(loop);
    record_until(arrival);
    const auto& e = graph.loops()[loop];
    const CondensedErrors alone =
        SolveCondensed(graph, chain_, {loop}, options_.convergence);
    alone_chi2_.push_back(alone.errors.solved ? alone.errors.total_chi2 : -1.0);
    const bool sample = alone.errors.solved && SamplesNoise(loop);
    if (sample) scale_.AddLoopSample(alone.errors.total_chi2);
    if (sample && arrival < loop_scales_.size()) {
      earliest_late = std::min(earliest_late, arrival);
    }
    const int c = clustering_.Add(loop, graph.ids()[e.from], graph.ids()[e.to]);
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
  record_until(graph.num_poses());
  if (earliest_late < graph.num_poses()) RecordScalesFrom(earliest_late);
}

template <class Pose>
void MapVerifier<Pose>::RecordScalesFrom(int pose) {
  std::vector<std::pair<int, double>> samples;  // (arrival, D²)
  for (int loop = 0; loop < static_cast<int>(alone_chi2_.size()); ++loop) {
    if (alone_chi2_[loop] >= 0.0 && SamplesNoise(loop)) {
      samples.emplace_back(this->poses_at_arrival(loop), alone_chi2_[loop]);
    }
  }
  loop_scales_.RecomputeFrom(pose, std::move(samples), Pose::kDof);
}

template <class Pose>
bool MapVerifier<Pose>::SamplesNoise(int loop) const {
  const auto& e = this->graph().loops()[loop];
  const Pose departure =
      chain_.Relative(e.from, e.to).inverse() * e.measurement;
  return departure.translation().norm() <
         kMostPlausibleDrift * chain_.Travelled(e.from, e.to);
}

template <class Pose>
int MapVerifier<Pose>::DecisionPose(int c, bool finish) const {
  const PoseGraph<Pose>& graph = this->graph();
  const int newest = graph.num_poses() - 1;
  int pose = records_[c].ready_pose;
  if (pose < 0) {
    pose = graph.IndexOf(clustering_.clusters()[c].start_high) +
           options_.cluster_window;
  }
  if (options_.noise_scale == 0.0) {
    // With an estimated scale, decisions wait for enough loops to sample it.
    const int known = loop_scales_.FirstWith(kMinLoopSamples);
    if (known < 0) return finish ? newest : -1;
    pose = std::max(pose, known);
  }
  if (pose > newest) return finish ? newest : -1;
  return pose + options_.decision_delay <= newest || finish ? pose : -1;
}

template <class Pose>
std::vector<DecisionChange> MapVerifier<Pose>::Judge(bool finish) {
  Catch();
  const auto& clusters = clustering_.clusters();
  std::vector<std::pair<int, int>> ready;  // (decision pose, cluster)
  auto still_pending = pending_.begin();
  for (const int c : pending_) {
    const int pose = DecisionPose(c, finish);
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
    ReopenWhileNeeded();
  }
  if (finish) {
    decision_pose_ = this->graph().num_poses() - 1;
    OptimizeMap();
    ReopenWhileNeeded();
  }
  return PublishStates();
}

template <class Pose>
std::vector<Pose> MapVerifier<Pose>::Map() {
  Catch();
  if (!map_) return {};
  return map_->Estimates();
}

template <class Pose>
std::vector<Pose> MapVerifier<Pose>::MapAt(const std::vector<int>& poses) {
  Catch();
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
      if (record.status == Status::kAccepted &&
          std::find(record.survivors.begin(), record.survivors.end(), loop) !=
              record.survivors.end()) {
        state = LoopState::kAccepted;
      } else if (record.status != Status::kPending) {
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
void MapVerifier<Pose>::JudgeCluster(int c) {
  ClusterRecord& record = records_[c];
  record.judged_scale = NoiseScaleAt(decision_pose_);
  IntraClusterOutcome intra = MapIntraCluster(
      this->graph(), chain_, clustering_.clusters()[c].loops, alone_chi2_,
      GroupScaleAt(decision_pose_), chi2_, options_.convergence);
  stats_.intra_solves += intra.solves;
  stats_.not_converged += intra.not_converged;
  this->CountSolves(intra.solves);
  record.refuted = intra.refuted;
  record.survivors = std::move(intra.survivors);
  record.left_out = std::move(intra.left_out);
  if (record.survivors.empty()) {
    record.status = Status::kRejected;
    touched_.push_back(c);
    return;
  }
  JudgeAgainstMap(c);
}

template <class Pose>
MapTrial MapVerifier<Pose>::TryAgainstMap(const std::vector<int>& links,
                                          double gate) {
  // Links in the map (a review) are tried as if they were not.
  const bool in_map = map_->Contains(links.front());
  const auto attempt = [&](int radius) {
    ++stats_.trials;
    this->CountSolves(1);
    return in_map ? map_->Retry(links, radius, Significant())
                  : map_->Try(links, radius);
  };
  MapTrial trial = attempt(options_.map_radius);
  // A near miss may be the held boundary's doing: look wider.
  if (trial.minimize.solved && trial.increase >= gate &&
      trial.increase < kNearMissFactor * gate) {
    trial = attempt(kWideRadiusFactor * options_.map_radius);
  }
  if (!trial.minimize.converged) ++stats_.not_converged;
  return trial;
}

template <class Pose>
bool MapVerifier<Pose>::EachLinkFits(
    const std::vector<double>& loop_chi2) const {
  const double one_link = Gate(Pose::kDof);
  return std::all_of(loop_chi2.begin(), loop_chi2.end(),
                     [&](double d2) { return d2 < one_link; });
}

template <class Pose>
bool MapVerifier<Pose>::Fits(const MapTrial& trial, double gate) const {
  return trial.minimize.solved && trial.increase < gate &&
         EachLinkFits(trial.loop_chi2);
}

template <class Pose>
MapTrial MapVerifier<Pose>::TryPart(int c, const std::vector<int>& part,
                                    bool* accepted) {
  const double gate = Gate(Pose::kDof * static_cast<int>(part.size()));
  MapTrial trial = TryAgainstMap(part, gate);
  *accepted = Fits(trial, gate);
  if (*accepted) {
    records_[c].survivors = part;
    AcceptTrial(c, trial.increase);
  }
  return trial;
}

template <class Pose>
bool MapVerifier<Pose>::Prune(int c, const MapTrial& failed) {
  const double one_link = Gate(Pose::kDof);
  std::vector<int> links = records_[c].survivors;
  std::vector<double> loop_chi2 = failed.loop_chi2;
  bool solved = failed.minimize.solved;
  for (int dropped = 0;
       dropped < kMostPrunedLinks && solved && links.size() > 1; ++dropped) {
    const auto worst = std::max_element(loop_chi2.begin(), loop_chi2.end());
    if (*worst < one_link) return false;
    links.erase(links.begin() + (worst - loop_chi2.begin()));
    bool accepted = false;
    MapTrial trial = TryPart(c, links, &accepted);
    if (accepted) {
      ++stats_.pruned;
      return true;
    }
    solved = trial.minimize.solved;
    loop_chi2 = std::move(trial.loop_chi2);
  }
  return false;
}

template <class Pose>
bool MapVerifier<Pose>::AcceptFittingLinks(int c, const MapTrial& failed) {
  if (!failed.minimize.solved) return false;
  const std::vector<int>& links = records_[c].survivors;
  const double one_link = Gate(Pose::kDof);
  std::vector<int> fitting;
  for (size_t k = 0; k < links.size(); ++k) {
    if (failed.loop_chi2[k] < one_link) fitting.push_back(links[k]);
  }
  if (fitting.empty() || fitting.size() == links.size()) return false;
  bool accepted = false;
  TryPart(c, fitting, &accepted);
  stats_.pruned += accepted;
  return accepted;
}

template <class Pose>
void MapVerifier<Pose>::AcceptTrial(int c, double increase) {
  map_->KeepTrial(Significant());
  scale_.SetClusterSample(
      c, increase, Pose::kDof * static_cast<int>(records_[c].survivors.size()));
  Accept(c, false);
}

template <class Pose>
double MapVerifier<Pose>::ClusterChi2AtEstimate(int c) const {
  double sum = 0.0;
  for (const int loop : records_[c].survivors) sum += map_->LoopChi2(loop);
  return sum;
}

template <class Pose>
void MapVerifier<Pose>::JudgeAgainstMap(int c) {
  const int e = Pose::kDof;
  const std::vector<int>& links = records_[c].survivors;
  const int dof = e * static_cast<int>(links.size());
  const double gate = Gate(dof);
  std::vector<double> link_chi2(links.size());
  std::transform(links.begin(), links.end(), link_chi2.begin(),
                 [&](int loop) { return map_->LoopChi2(loop); });
  const double at_estimate =
      std::accumulate(link_chi2.begin(), link_chi2.end(), 0.0);
  if (at_estimate < gate && EachLinkFits(link_chi2)) {
    ++stats_.quick_accepts;
    scale_.SetClusterSample(c, at_estimate, dof);
    Accept(c, true);
    return;
  }
  const int wide = kWideRadiusFactor * options_.map_radius;
  const MapTrial trial = TryAgainstMap(links, gate);
  if (Fits(trial, gate)) {
    AcceptTrial(c, trial.increase);
    return;
  }
  if (Prune(c, trial)) return;
  // Conflict. The accepted clusters the trial strained most, more than c
  // is left unsatisfied (each normalized by its gate), are set aside in turn
  // while c still does not fit; if c then fits, they stay out (reversals),
  // else they are restored and c is set aside.
  const double unsatisfied =
      std::accumulate(trial.loop_chi2.begin(), trial.loop_chi2.end(), 0.0) /
      gate;
  const std::vector<std::pair<double, int>> strained = ClustersStrainedAbove(
      trial.map_loops, this->cluster_of_loop_,
      [&](int a) {
        return Gate(e * static_cast<int>(records_[a].survivors.size()));
      },
      unsatisfied);
  std::vector<int> removed;
  size_t removed_links = 0;
  for (const auto& [strain, a] : strained) {
    if (removed.size() == kMostReversalsPerConflict) break;
    removed_links += records_[a].survivors.size();
    if (records_[c].refuted && removed_links >= links.size()) break;
    map_->Remove(records_[a].survivors, wide, Significant());
    removed.push_back(a);
    ++stats_.trials;
    this->CountSolves(1);
    const MapTrial without = map_->Try(links, wide);
    if (Fits(without, gate)) {
      AcceptTrial(c, without.increase);
      for (const int r : removed) {
        ++stats_.reversals;
        records_[r].status = Status::kSetAside;
        scale_.RemoveClusterSample(r);
        touched_.push_back(r);
      }
      reopen_needed_ = true;
      return;
    }
  }
  for (auto it = removed.rbegin(); it != removed.rend(); ++it) {
    map_->Add(records_[*it].survivors, wide, Significant());
  }
  if (AcceptFittingLinks(c, trial)) return;
  SetAside(c);
}

template <class Pose>
void MapVerifier<Pose>::Accept(int c, bool add_to_map) {
  ClusterRecord& record = records_[c];
  if (add_to_map)
    map_->Add(record.survivors, options_.map_radius, Significant());
  record.status = Status::kAccepted;
  touched_.push_back(c);
  ++accepted_clusters_;
  if (++accepted_since_optimize_ >=
      std::max<double>(options_.optimize_every,
                       options_.optimize_growth * accepted_clusters_)) {
    OptimizeMap();
  }
}

template <class Pose>
void MapVerifier<Pose>::SetAside(int c) {
  if (records_[c].status == Status::kAccepted) {
    LeaveMap(c);
    scale_.RemoveClusterSample(c);
    reopen_needed_ = true;
    return;
  }
  records_[c].status = Status::kSetAside;
  touched_.push_back(c);
}

template <class Pose>
void MapVerifier<Pose>::LeaveMap(int c) {
  map_->Remove(records_[c].survivors, options_.map_radius, Significant());
  records_[c].status = Status::kSetAside;
  touched_.push_back(c);
}

template class MapVerifier<Pose2>;
template class MapVerifier<Pose3>;

}  // namespace rrr
