// Worlds of several odometry chains for the tests of the chains' rules.
#ifndef RRR_CORE_TESTING_CHAIN_WORLDS_H_
#define RRR_CORE_TESTING_CHAIN_WORLDS_H_

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include "rrr/geometry/pose2.h"
#include "rrr/graph/chain_spans.h"
#include "rrr/graph/keyframe_track.h"
#include "rrr/graph/odometry_noise.h"
#include "rrr/graph/pose_graph.h"
#include "rrr/rrr/map/verify_with_map.h"
#include "rrr/rrr/options.h"
#include "rrr/sim/false_loops.h"
#include "rrr/sim/simulated_world.h"

namespace rrr::testing {

// Appends `world` to `graph` as a new chain: its poses (ids after the
// graph's), its odometry and its loops, the estimates moved by `moved` (a
// session whose odometry starts elsewhere). Returns the first pose's index.
inline int AppendChain(const SimulatedWorld& world, const Pose2& moved,
                       PoseGraph<Pose2>* graph) {
  const int first = graph->num_poses();
  const PoseId id0 = first == 0 ? 0 : graph->ids().back() + 2;
  for (int k = 0; k < world.graph.num_poses(); ++k) {
    graph->AddPose(id0 + k, moved * world.graph.estimates()[k]);
  }
  for (auto e : world.graph.odometry()) {
    e.from += first;
    e.to += first;
    graph->AddEdge(e);
  }
  for (auto e : world.graph.loops()) {
    e.from += first;
    e.to += first;
    graph->AddEdge(e);
  }
  return first;
}

// One world's graph cut into sessions at the poses `cuts` (ascending): the
// odometry edge into each removed, each later session's estimates restarted
// elsewhere. Loops across a cut become loops between the chains.
inline PoseGraph<Pose2> CutAt(const PoseGraph<Pose2>& graph,
                              const std::vector<int>& cuts) {
  PoseGraph<Pose2> out;
  Pose2 restart;
  for (int k = 0, next = 0; k < graph.num_poses(); ++k) {
    if (next < static_cast<int>(cuts.size()) && k == cuts[next]) {
      ++next;
      restart = Pose2(40.0 * next, -25.0, 1.2 * next) *
                graph.estimates()[k].inverse();
    }
    out.AddPose(graph.ids()[k], restart * graph.estimates()[k]);
  }
  for (const auto& e : graph.odometry()) {
    const int later = std::max(e.from, e.to);
    if (std::find(cuts.begin(), cuts.end(), later) == cuts.end()) {
      out.AddEdge(e);
    }
  }
  for (const auto& e : graph.loops()) out.AddEdge(e);
  return out;
}

inline WorldOptions Grid(int poses, std::uint64_t seed) {
  WorldOptions options;
  options.poses = poses;
  options.false_loops = 0;
  options.seed = seed;
  return options;
}

inline RrrOptions ChainWorldOptions() {
  RrrOptions options;
  options.cluster_window = 10;
  return options;
}

// `world` cut into two sessions at pose `cut`, with 200 false loops
// between them (random, seed 3) after its `*true_loops` true ones.
inline PoseGraph<Pose2> TwoSessionsWithFalseLoops(const SimulatedWorld& world,
                                                  int cut, size_t* true_loops) {
  PoseGraph<Pose2> two = CutAt(world.graph, {cut});
  *true_loops = two.loops().size();
  FalseLoopOptions spoil;
  spoil.count = 200;
  spoil.between_chains = true;
  spoil.seed = 3;
  AddFalseLoops(&two, spoil);
  return two;
}

// `world` cut into sessions at the poses `cuts` (ascending), with a false
// revisit of `links` links inside the second after its `*true_loops` true
// loops:
// from pose cuts[0] + 100 + k to cuts[0] + 500 + k (the second session must
// hold them), measuring what the odometry between them says moved 2 m ahead
// and 0.06 rad: the odometry's drift over 400 poses can explain it, so the
// second session alone need not refute it.
inline PoseGraph<Pose2> SessionsWithAFalseRevisit(const SimulatedWorld& world,
                                                  const std::vector<int>& cuts,
                                                  size_t* true_loops,
                                                  int links = 10) {
  PoseGraph<Pose2> out = CutAt(world.graph, cuts);
  *true_loops = out.loops().size();
  for (int k = 0; k < links; ++k) {
    Constraint<Pose2> e = out.loops().front();
    e.from = cuts[0] + 100 + k;
    e.to = e.from + 400;
    e.measurement =
        world.graph.estimates()[e.from].between(world.graph.estimates()[e.to]) *
        Pose2(2.0, 0.0, 0.06);
    out.AddEdge(e);
  }
  return out;
}

// Chain `span` of `graph` judged alone by the map procedure (options
// ChainWorldOptions): the verdict over its own loops, whose indices in
// `graph` `*inside` receives (the verdict's loop k is (*inside)[k]).
inline Verdict JudgedAlone(const PoseGraph<Pose2>& graph, const ChainSpan& span,
                           std::vector<int>* inside) {
  inside->clear();
  for (size_t k = 0; k < graph.loops().size(); ++k) {
    const auto& e = graph.loops()[k];
    if (span.Holds(e.from) && span.Holds(e.to)) {
      inside->push_back(static_cast<int>(k));
    }
  }
  return VerifyWithMap(SubGraph(graph, {span}, graph.estimates(), *inside),
                       ChainWorldOptions());
}

// `world` (of at least 1,000 poses) cut into three sessions at `cuts`
// (two poses, ascending). The first two never revisit each other's places;
// between them come about 80 random false loops and two false revisits of two
// links each that agree on one wrong placement of the second session (the
// same look-alike offset twice, as in a building whose floors repeat), at
// poses 100 and 130 of the first and 700 and 730. Those between the third and
// each of the others are the world's true loops. The first `*true_loops`
// loops are true.
inline PoseGraph<Pose2> ThreeSessionsWithAFalseJoin(
    const SimulatedWorld& world, const std::vector<int>& cuts,
    size_t* true_loops) {
  const PoseGraph<Pose2> cut = CutAt(world.graph, cuts);
  const auto first_two = [&](const Constraint<Pose2>& e) {
    return std::min(e.from, e.to) < cuts[0] &&
           std::max(e.from, e.to) >= cuts[0] &&
           std::max(e.from, e.to) < cuts[1];
  };
  PoseGraph<Pose2> three;
  for (int p = 0; p < cut.num_poses(); ++p) {
    three.AddPose(cut.ids()[p], cut.estimates()[p]);
  }
  for (const auto& e : cut.odometry()) three.AddEdge(e);
  for (const auto& e : cut.loops()) {
    if (!first_two(e)) three.AddEdge(e);
  }
  *true_loops = three.loops().size();
  // The false revisits agree exactly with each session's own map.
  std::vector<Pose2> maps(three.num_poses());
  for (const ChainSpan& span : ChainSpansOf(three)) {
    std::vector<int> inside;
    for (size_t k = 0; k < three.loops().size(); ++k) {
      if (span.Holds(three.loops()[k].from) &&
          span.Holds(three.loops()[k].to)) {
        inside.push_back(static_cast<int>(k));
      }
    }
    std::vector<Pose2> map;
    VerifyWithMap(SubGraph(three, {span}, three.estimates(), inside),
                  ChainWorldOptions(), &map);
    std::copy(map.begin(), map.end(), maps.begin() + span.first);
  }
  const Pose2 look_alike(6.0, -4.0, 0.4);
  for (const auto& [i, j] : {std::pair(100, 700), std::pair(130, 730)}) {
    for (int k = 0; k < 2; ++k) {
      Constraint<Pose2> e;
      e.from = i + k;
      e.to = j + k;
      e.measurement = maps[e.from].between(look_alike * maps[e.to]);
      e.information = three.loops().front().information;
      three.AddEdge(e);
    }
  }
  // Random false loops between any two sessions; those between the first
  // two kept.
  PoseGraph<Pose2> drawn = three;
  FalseLoopOptions spoil;
  spoil.count = 240;
  spoil.between_chains = true;
  spoil.seed = 4;
  const size_t before = drawn.loops().size();
  AddFalseLoops(&drawn, spoil);
  for (size_t k = before; k < drawn.loops().size(); ++k) {
    if (first_two(drawn.loops()[k])) three.AddEdge(drawn.loops()[k]);
  }
  return three;
}

// A robot's odometry readings over poses first..last of `graph`: its pose in
// its odometry frame composed from the identity at `first` (an odometry that
// starts at zero), stamped 20 ms apart from `stamp_ns`, each with the
// covariance a source reports when its motions have the graph's odometry
// information.
inline std::vector<KeyframeRecord<Pose2>> Readings(
    const PoseGraph<Pose2>& graph, int first, int last, std::int64_t stamp_ns) {
  std::vector<KeyframeRecord<Pose2>> readings(1);
  readings[0].stamp_ns = stamp_ns;
  for (const auto& e : graph.odometry()) {
    if (e.to <= first || e.to > last) continue;
    KeyframeRecord<Pose2> next;
    next.stamp_ns = readings.back().stamp_ns + 20'000'000;
    next.odometry_pose = readings.back().odometry_pose * e.measurement;
    next.covariance = OdometryNoiseModel<Pose2>::Grow(
        readings.back().covariance, next.odometry_pose, e.information);
    readings.push_back(next);
  }
  return readings;
}

}  // namespace rrr::testing

#endif  // RRR_CORE_TESTING_CHAIN_WORLDS_H_
