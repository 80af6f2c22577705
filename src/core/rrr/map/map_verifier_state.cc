// MapVerifier's state written and read back (OnlineVerifier::SaveState).
#include <algorithm>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/io/byte_stream.h"
#include "rrr/rrr/map/map_verifier.h"

namespace rrr {
namespace {

constexpr char kStateFamily[] = "rrr map procedure state, version ";
constexpr char kStateFormat[] = "rrr map procedure state, version 7";

// The options that the map procedure's decisions depend on, as bytes: a
// state saved under others is not restored (those of the published
// procedure alone, such as `iterations`, do not count).
std::string DecisionOptions(const RrrOptions& o, int dof) {
  ByteWriter out;
  for (const std::int64_t v :
       {static_cast<std::int64_t>(dof), static_cast<std::int64_t>(o.procedure),
        static_cast<std::int64_t>(o.cluster_window),
        static_cast<std::int64_t>(o.max_future_poses),
        static_cast<std::int64_t>(o.max_waiting),
        static_cast<std::int64_t>(o.decision_delay),
        static_cast<std::int64_t>(o.map_radius),
        static_cast<std::int64_t>(o.map_junctions),
        static_cast<std::int64_t>(o.optimize_every),
        static_cast<std::int64_t>(o.convergence.max_iterations)}) {
    out.Int(v);
  }
  for (const double v : {o.alpha, o.noise_scale, o.noise_margin,
                         o.optimize_growth, o.convergence.relative_decrease}) {
    out.Double(v);
  }
  return out.bytes();
}

// Reads the format and the options of a state: "" for a state of an earlier
// version of the map procedure (its decisions were another rule's, so it is
// not restored: the updates run again). Throws std::runtime_error if it is
// not a state of the map procedure.
std::string OptionsOfState(ByteReader* in) {
  const std::string format = in->Text("the format");
  if (format == kStateFormat) return in->Text("the options");
  if (format.rfind(kStateFamily, 0) == 0) return {};
  throw std::runtime_error("it is not a state of the map procedure");
}

}  // namespace

template <class Pose>
template <class Stream, class Self>
void MapVerifier<Pose>::TransferState(Stream* io, Self* self) {
  io->Size(&self->records_, 4 * sizeof(std::int64_t), "cluster records");
  for (auto& r : self->records_) {
    io->Field(&r.status, "a cluster's status", Status::kRefused);
    io->Field(&r.accepted, "a cluster's accepted links");
    io->Field(&r.ready_pose, "a cluster's ready pose");
    io->Field(&r.conflicts, "a cluster's conflicts");
  }
  io->Field(&self->pending_, "the pending clusters");
  io->Field(&self->alone_chi2_, "the loops' errors alone");
  io->Size(&self->reasons_, 7 * sizeof(double), "the decisions' reasons");
  for (auto& r : self->reasons_) {
    io->Field(&r.test, "a decision's test", DecisionTest::kOutweighed);
    io->Field(&r.statistic, "a decision's statistic");
    io->Field(&r.gate, "a decision's gate");
    io->Field(&r.scale, "a decision's scale");
    io->Field(&r.dof, "a decision's degrees of freedom");
    io->Field(&r.pose, "a decision's pose");
    io->Field(&r.by_cluster, "the cluster that outweighed a link");
  }
  io->Field(&self->touched_, "the changed clusters");
  io->Field(&self->decision_pose_, "the decision pose");
  io->Field(&self->judged_until_, "the pose judged until");
  io->Field(&self->accepted_since_optimize_,
            "the acceptances since optimizing");
  io->Field(&self->accepted_clusters_, "the acceptances");
  io->Field(&self->arbiter_due_, "whether the arbiter is due");
  auto& stats = self->stats_;
  for (auto* v : {&stats.own_solves, &stats.trials, &stats.quick_accepts,
                  &stats.reversals, &stats.rejudged, &stats.optimizations,
                  &stats.not_converged}) {
    io->Field(v, "a statistic");
  }
}

template <class Pose>
std::string MapVerifier<Pose>::SaveState() const {
  ByteWriter out;
  out.Text(kStateFormat);
  out.Text(DecisionOptions(options_, Pose::kDof));
  this->SaveRecord(&out);
  clustering_.Save(&out);
  TransferState(&out, this);
  out.Int(chain_.num_poses());
  out.Int(map_ ? 1 : 0);
  if (map_) map_->Save(&out);
  scale_.Save(&out);
  return out.bytes();
}

template <class Pose>
bool MapVerifier<Pose>::SavedUnderSameOptions(const std::string& state) const {
  ByteReader in(state);
  return OptionsOfState(&in) == DecisionOptions(options_, Pose::kDof);
}

template <class Pose>
void MapVerifier<Pose>::CheckRestored() const {
  const int clusters = static_cast<int>(clustering_.clusters().size());
  const int loops = static_cast<int>(alone_chi2_.size());
  if (static_cast<int>(records_.size()) != clusters ||
      static_cast<int>(reasons_.size()) != loops ||
      static_cast<int>(this->cluster_of_loop_.size()) != loops) {
    throw std::runtime_error(
        "the state has " + std::to_string(records_.size()) +
        " cluster records for " + std::to_string(clusters) + " clusters and " +
        std::to_string(reasons_.size()) + " reasons and " +
        std::to_string(this->cluster_of_loop_.size()) + " clusters of loops" +
        " for " + std::to_string(loops) + " loops");
  }
  // Every index the state holds must name what the state has.
  const auto within = [](int value, int low, int high, const char* what) {
    if (value < low || value > high) {
      throw std::runtime_error(
          std::string(what) + " is " + std::to_string(value) + ", outside " +
          std::to_string(low) + ".." + std::to_string(high));
    }
  };
  const auto all_within = [&](const std::vector<int>& values, int count,
                              const char* what) {
    for (const int v : values) within(v, 0, count - 1, what);
  };
  const int poses = this->graph().num_poses();
  all_within(this->cluster_of_loop_, clusters, "a loop's cluster");
  for (const Cluster& c : clustering_.clusters()) {
    all_within(c.loops, loops, "a cluster's loop");
  }
  const int most_dof = Pose::kDof * loops;
  for (const DecisionReason& r : reasons_) {
    within(r.by_cluster, -1, clusters - 1,
           "the cluster that outweighed a link");
    within(r.dof, 0, most_dof, "a decision's degrees of freedom");
  }
  for (const ClusterRecord& r : records_) {
    all_within(r.accepted, loops, "an accepted link");
    for (const int loop : r.accepted) {
      within(reasons_[loop].dof, Pose::kDof, most_dof,
             "an accepted link's degrees of freedom");
    }
    all_within(r.conflicts, clusters, "a cluster's conflict");
    within(r.ready_pose, -1, poses - 1, "a cluster's ready pose");
  }
  all_within(pending_, clusters, "a pending cluster");
  all_within(touched_, clusters, "a changed cluster");
  within(judged_until_, -1, poses - 1, "the pose judged until");
  within(decision_pose_, 0, std::max(poses - 1, 0), "the decision pose");
  // Each loop is its cluster's, accepted links ascend (the rule searches
  // them), and the map holds exactly the links of the accepted clusters.
  for (int c = 0; c < clusters; ++c) {
    const ClusterRecord& r = records_[c];
    if ((r.status == Status::kAccepted) == r.accepted.empty()) {
      throw std::runtime_error("cluster " + std::to_string(c) + " has " +
                               std::to_string(r.accepted.size()) +
                               " accepted links in its state");
    }
    if (std::adjacent_find(r.accepted.begin(), r.accepted.end(),
                           std::greater_equal<int>()) != r.accepted.end()) {
      throw std::runtime_error("cluster " + std::to_string(c) +
                               " lists its accepted links out of order");
    }
    for (const auto* of : {&clustering_.clusters()[c].loops, &r.accepted}) {
      for (const int loop : *of) {
        if (this->cluster_of_loop_[loop] != c) {
          throw std::runtime_error("cluster " + std::to_string(c) +
                                   " names loop " + std::to_string(loop) +
                                   " of another cluster");
        }
      }
    }
  }
  for (int loop = 0; loop < loops; ++loop) {
    const std::vector<int>& accepted =
        records_[this->cluster_of_loop_[loop]].accepted;
    const bool in_map = map_ && map_->Contains(loop);
    if (in_map != std::binary_search(accepted.begin(), accepted.end(), loop)) {
      throw std::runtime_error("loop " + std::to_string(loop) + " is " +
                               (in_map ? "in the map but not accepted"
                                       : "accepted but not in the map"));
    }
  }
}

template <class Pose>
void MapVerifier<Pose>::RestoreState(const std::string& state) {
  ByteReader in(state);
  if (OptionsOfState(&in) != DecisionOptions(options_, Pose::kDof)) {
    throw std::runtime_error("the state was saved under other options");
  }
  this->RestoreRecord(&in);
  const PoseGraph<Pose>& graph = this->graph();
  clustering_.Restore(&in);
  TransferState(&in, this);
  const std::int64_t chain_poses = in.Int("the chain's length");
  if (chain_poses < 1 || chain_poses > graph.num_poses()) {
    throw std::runtime_error(
        "the state's chain has " + std::to_string(chain_poses) +
        " poses, the graph " + std::to_string(graph.num_poses()));
  }
  for (int k = chain_.num_poses(); k < chain_poses; ++k) {
    const auto& e = graph.odometry()[k - 1];
    chain_.Append(e.measurement, e.information);
  }
  if (in.Int("whether there is a map") != 0) {
    map_ = std::make_unique<MaintainedMap<Pose>>(
        graph, chain_, options_.convergence, options_.map_junctions);
    map_->Restore(&in);
  }
  CheckRestored();
  scale_.Restore(&in, graph.num_poses());
  if (!in.AtEnd()) throw std::runtime_error("the state goes on past its end");
}

template std::string MapVerifier<Pose2>::SaveState() const;
template std::string MapVerifier<Pose3>::SaveState() const;
template bool MapVerifier<Pose2>::SavedUnderSameOptions(
    const std::string&) const;
template bool MapVerifier<Pose3>::SavedUnderSameOptions(
    const std::string&) const;
template void MapVerifier<Pose2>::RestoreState(const std::string&);
template void MapVerifier<Pose3>::RestoreState(const std::string&);

}  // namespace rrr
