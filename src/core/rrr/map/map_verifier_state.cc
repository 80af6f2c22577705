// MapVerifier's state written and read back (OnlineVerifier::SaveState).
#include <stdexcept>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/io/byte_stream.h"
#include "rrr/rrr/map/map_verifier.h"

namespace rrr {
namespace {

constexpr char kStateFamily[] = "rrr map procedure state, version ";
constexpr char kStateFormat[] = "rrr map procedure state, version 5";

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

// Reads `what`, a value of the enum of `last` from 0 to `last`. Throws
// std::runtime_error naming it if it is out of that range.
template <class Enum>
Enum ReadEnum(ByteReader* in, Enum last, const char* what) {
  const std::int64_t value = in->Int(what);
  if (value < 0 || value > static_cast<std::int64_t>(last)) {
    throw std::runtime_error(std::string(what) + " has the unknown value " +
                             std::to_string(value));
  }
  return static_cast<Enum>(value);
}

}  // namespace

template <class Pose>
std::string MapVerifier<Pose>::SaveState() const {
  ByteWriter out;
  out.Text(kStateFormat);
  out.Text(DecisionOptions(options_, Pose::kDof));
  this->SaveRecord(&out);
  clustering_.Save(&out);
  out.Int(static_cast<std::int64_t>(records_.size()));
  for (const ClusterRecord& r : records_) {
    out.Int(static_cast<std::int64_t>(r.status));
    out.Ints(r.accepted);
    out.Int(r.ready_pose);
    out.Ints(r.conflicts);
  }
  out.Ints(pending_);
  out.Doubles(alone_chi2_);
  for (const DecisionReason& r : reasons_) {
    out.Int(static_cast<std::int64_t>(r.test));
    for (const double v : {r.statistic, r.gate, r.scale}) out.Double(v);
    for (const int v : {r.dof, r.pose, r.by_cluster}) out.Int(v);
  }
  out.Ints(touched_);
  out.Int(chain_.num_poses());
  out.Int(map_ ? 1 : 0);
  if (map_) map_->Save(&out);
  scale_.Save(&out);
  for (const int v :
       {decision_pose_, judged_until_, accepted_since_optimize_,
        accepted_clusters_, static_cast<int>(arbiter_due_), stats_.own_solves,
        stats_.trials, stats_.quick_accepts, stats_.reversals, stats_.rejudged,
        stats_.optimizations, stats_.not_converged}) {
    out.Int(v);
  }
  return out.bytes();
}

template <class Pose>
bool MapVerifier<Pose>::SavedUnderSameOptions(const std::string& state) const {
  ByteReader in(state);
  return OptionsOfState(&in) == DecisionOptions(options_, Pose::kDof);
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
  records_.resize(in.Count("cluster records", 4 * sizeof(std::int32_t)));
  if (records_.size() != clustering_.clusters().size()) {
    throw std::runtime_error(
        "the state has " + std::to_string(records_.size()) +
        " cluster records for " +
        std::to_string(clustering_.clusters().size()) + " clusters");
  }
  for (ClusterRecord& r : records_) {
    r.status = ReadEnum(&in, Status::kRefused, "a cluster's status");
    r.accepted = in.Ints("a cluster's accepted links");
    r.ready_pose = static_cast<int>(in.Int("a cluster's ready pose"));
    r.conflicts = in.Ints("a cluster's conflicts");
    for (const int a : r.conflicts) {
      if (a < 0 || a >= static_cast<int>(records_.size())) {
        throw std::runtime_error("a cluster's conflict names cluster " +
                                 std::to_string(a));
      }
    }
  }
  pending_ = in.Ints("the pending clusters");
  alone_chi2_ = in.Doubles("the loops' errors alone");
  reasons_.resize(alone_chi2_.size());
  for (DecisionReason& r : reasons_) {
    r.test = ReadEnum(&in, DecisionTest::kOutweighed, "a decision's test");
    for (double* v : {&r.statistic, &r.gate, &r.scale}) {
      *v = in.Double("a decision's figure");
    }
    for (int* v : {&r.dof, &r.pose, &r.by_cluster}) {
      *v = static_cast<int>(in.Int("a decision's figure"));
    }
  }
  touched_ = in.Ints("the changed clusters");
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
  scale_.Restore(&in);
  for (int* v : {&decision_pose_, &judged_until_, &accepted_since_optimize_,
                 &accepted_clusters_}) {
    *v = static_cast<int>(in.Int("a counter"));
  }
  arbiter_due_ = in.Int("whether the arbiter is due") != 0;
  for (int* v : {&stats_.own_solves, &stats_.trials, &stats_.quick_accepts,
                 &stats_.reversals, &stats_.rejudged, &stats_.optimizations,
                 &stats_.not_converged}) {
    *v = static_cast<int>(in.Int("a statistic"));
  }
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
