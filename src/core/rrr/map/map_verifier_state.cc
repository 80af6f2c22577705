// MapVerifier's state written and read back (OnlineVerifier::SaveState).
#include <cstdint>
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
constexpr char kStateFormat[] = "rrr map procedure state, version 10";

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
  io->Size(&self->records_, 2 * sizeof(std::int64_t), "cluster records");
  for (auto& r : self->records_) {
    io->Field(&r.status, "a cluster's status", Status::kHeld);
    io->Field(&r.ready_pose, "a cluster's ready pose");
  }
  io->Field(&self->alone_chi2_, "the loops' errors alone");
  io->Size(&self->reasons_, 7 * sizeof(double), "the decisions' reasons");
  for (auto& r : self->reasons_) {
    io->Field(&r.test, "a decision's test", DecisionTest::kApart);
    io->Field(&r.statistic, "a decision's statistic");
    io->Field(&r.gate, "a decision's gate");
    io->Field(&r.scale, "a decision's scale");
    io->Field(&r.dof, "a decision's degrees of freedom");
    io->Field(&r.pose, "a decision's pose");
    io->Field(&r.by_cluster, "the cluster that outweighed a link");
  }
  io->Field(&self->judged_until_, "the pose judged until");
  io->Field(&self->accepted_since_optimize_,
            "the acceptances since optimizing");
  io->Field(&self->accepted_clusters_, "the acceptances");
  auto& stats = self->stats_;
  for (auto* v : {&stats.own_solves, &stats.trials, &stats.quick_accepts,
                  &stats.reversals, &stats.rejudged, &stats.optimizations,
                  &stats.not_converged, &stats.joins, &stats.join_revisions}) {
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
void MapVerifier<Pose>::CompleteRestored() {
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
  const int poses = this->graph().num_poses();
  for (const int c : this->cluster_of_loop_) {
    within(c, 0, clusters - 1, "a loop's cluster");
  }
  const int most_dof = Pose::kDof * loops;
  for (const DecisionReason& r : reasons_) {
    within(r.by_cluster, -1, clusters - 1,
           "the cluster that outweighed a link");
    within(r.dof, 0, most_dof, "a decision's degrees of freedom");
  }
  for (const ClusterRecord& r : records_) {
    within(r.ready_pose, -1, poses - 1, "a cluster's ready pose");
  }
  within(judged_until_, -1, poses - 1, "the pose judged until");
  // Each cluster's loops are its own and ascend, and so do the accepted
  // links taken from them (the rule binary-searches those).
  int accepted = 0;
  pending_.clear();
  for (int c = 0; c < clusters; ++c) {
    const std::vector<int>& of = clustering_.clusters()[c].loops;
    ClusterRecord& r = records_[c];
    r.accepted.clear();
    for (size_t k = 0; k < of.size(); ++k) {
      within(of[k], k == 0 ? 0 : of[k - 1] + 1, loops - 1,
             "a cluster's loop (they ascend)");
      if (this->cluster_of_loop_[of[k]] != c) {
        throw std::runtime_error("cluster " + std::to_string(c) +
                                 " names loop " + std::to_string(of[k]) +
                                 " of another cluster");
      }
      if (map_ && map_->Contains(of[k])) r.accepted.push_back(of[k]);
    }
    // A judged cluster's chains are the map's; a held one's in two maps.
    const auto [a, b] = ChainsOf(c);
    const bool judged = r.status != Status::kPending;
    within(std::min(a, b), 0, this->num_chains() - 1, "a cluster's chain");
    within(std::max(a, b), 0,
           (judged && map_ ? map_->num_chains()
            : judged       ? 0
                           : this->num_chains()) -
               1,
           "the chain of a cluster");
    if (r.status == Status::kHeld && map_->MapOf(a) == map_->MapOf(b)) {
      throw std::runtime_error("cluster " + std::to_string(c) +
                               " waits for a join of chains in one map");
    }
    if ((r.status == Status::kAccepted) == r.accepted.empty()) {
      throw std::runtime_error("cluster " + std::to_string(c) + " has " +
                               std::to_string(r.accepted.size()) +
                               " links in the map and another status");
    }
    if (r.status == Status::kPending) pending_.push_back(c);
    accepted += static_cast<int>(r.accepted.size());
  }
  if (map_ && map_->num_loops() != accepted) {
    throw std::runtime_error(
        "the map holds " + std::to_string(map_->num_loops()) +
        " loops, the clusters " + std::to_string(accepted));
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
  if (in.Int("whether there is a map") != 0) {
    map_ = std::make_unique<MaintainedMap<Pose>>(
        graph, this->chains(), options_.convergence, options_.map_junctions);
    map_->Restore(&in);
  }
  CompleteRestored();
  scale_.Restore(&in, graph.num_poses(), static_cast<int>(alone_chi2_.size()));
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
