// The map RRR keeps between decisions: odometry and the accepted loops.
#ifndef RRR_SOLVER_MAINTAINED_MAP_H_
#define RRR_SOLVER_MAINTAINED_MAP_H_

#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <vector>

#include "rrr/graph/chain_odometry.h"
#include "rrr/graph/pose_graph.h"
#include "rrr/io/byte_stream.h"
#include "rrr/solver/local_problem.h"

namespace rrr {

// What adding some loops to the map would do, found by minimizing the map's
// error with them over the poses near their ends (MaintainedMap::Try).
struct MapTrial {
  // Δ: the minimal error of the local problem with the loops minus its
  // minimal error without them (both minimized over the same region, the
  // rest held). When the rest of the map is at its optimum, holding it can
  // only raise the first minimum, so Δ bounds the increase of the whole
  // map's minimal error from above.
  double increase = 0.0;
  // d²_l of each tried loop after the minimization, in the order given.
  std::vector<double> loop_chi2;
  // Every loop of the map in the local problem, with d²_l before and after
  // the minimization, by loop index.
  struct LoopStrain {
    int loop;
    double before, after;
  };
  std::vector<LoopStrain> map_loops;
  MinimizeResult minimize;
  int num_free = 0;  // poses minimized
  // Chains whose frame the minimum left free (a test of loops between
  // chains against their odometry alone): the loops' error has e dof fewer
  // per such chain.
  int free_frames = 0;
};

// Odometry plus a set of accepted loops of a graph of one or several
// odometry chains (ChainOdometry), with an estimate near the minimum of
// their error. Only the poses that loops touch (junctions) are variables:
// the odometry between consecutive junctions of a chain is one condensed
// edge, so the cost of every operation depends on the loops and junctions
// it reaches, not on the length of the chains. The estimate of any other
// pose is its optimum given the junctions next to it; poses after a chain's
// last junction follow it by odometry.
//
// Chains joined by loops of the map, directly or through others, make one
// map, held in the frame of its lowest chain: that chain's first pose is
// held (the map's anchor), every other pose is free. A chain joined to no
// other is a map of its own. Every chain's first pose is a junction.
//
// Changes are local: Add, Remove and Try minimize over the junctions within
// `radius` hops (along a chain or across a loop of the map) of the loops'
// ends, and no further than the hop layer that brings them to
// `most_junctions`; Optimize minimizes over every map.
template <class Pose>
class MaintainedMap {
 public:
  // The map of `graph`'s chains `chains`, each taken in as AddChain does.
  // Both must outlive the map; poses may be added to both between calls,
  // and chains, which AddChain then takes in.
  MaintainedMap(const PoseGraph<Pose>& graph, const ChainOdometry<Pose>& chains,
                const ConvergenceOptions& convergence, int most_junctions);

  // Takes chain `chain` of the chains in, a map of its own with its first
  // pose at its estimate in the graph. Chains are taken in in order: throws
  // std::logic_error for another.
  void AddChain(int chain);

  // The chains taken in (AddChain).
  int num_chains() const { return static_cast<int>(map_of_.size()); }
  bool Contains(int loop) const;
  int num_loops() const { return num_loops_; }
  int num_junctions() const { return static_cast<int>(junctions_.size()); }
  // The map chain `chain` is in: the lowest chain joined with it by the
  // map's loops (itself if none).
  int MapOf(int chain) const { return map_of_[chain]; }
  // The map chain `chain` would be in were the map's loops between chains
  // `a` and `b` taken out: whether they are the only tie between two parts.
  int MapOfWithout(int chain, int a, int b) const;

  // d²_l of graph loop `loop` at the current estimate (its ends in one map).
  double LoopChi2(int loop) const;
  // The estimate of pose `pose`, in its map's frame.
  Pose Estimate(int pose) const;
  // The estimate of every pose of the graph, up to `threads` poses at a time
  // (the same estimates whatever their number).
  std::vector<Pose> Estimates(int threads = 1) const;

  // What adding `loops` (not in the map, their ends in one map) would do.
  // The region is first minimized without them, and that improvement of the
  // estimate is kept; otherwise the map is unchanged until KeepTrial().
  // With a finite `fails_above`, the minimization with them stops once Δ
  // could not come under it (LocalProblem::Minimize's reach): a trial that
  // cannot pass a gate of `fails_above` is not minimized to the end.
  MapTrial Try(const std::vector<int>& loops, int radius,
               double fails_above = std::numeric_limits<double>::infinity());
  // `trial`, the last Try(loops, radius), fails `passes`: tries them again
  // over twice the hops, and again, while the region grows, a widening
  // lowers Δ by more than `significant` (the correction reaches the
  // region's border) and Δ is not over `gate` by more than the last
  // widening lowered it (the correction fades as the region grows: no
  // further widening brings it under). Each wider trial stops once Δ could
  // not come under `gate` (Try's `fails_above`). Returns the last trial (the
  // one kept); `*tries` counts the trials made.
  MapTrial Widen(MapTrial trial, const std::vector<int>& loops, int radius,
                 double gate, double significant,
                 const std::function<bool(const MapTrial&)>& passes,
                 int* tries);
  // Adds the loops of the last Try() with the estimate it found, then
  // relaxes as Relax(loops, 2 · its radius, significant): its own region is
  // at its minimum already, twice the radius is the first wider one (the
  // map is kept near its minimum, the premise of a trial's bound). Throws
  // std::logic_error if the map changed since (another Try, Add, Remove,
  // Move or Optimize).
  void KeepTrial(double significant);
  // Adds `loops` and minimizes near them (Relax).
  void Add(const std::vector<int>& loops, int radius, double significant);
  // Removes `loops` (in the map) and minimizes near their ends (Relax). A
  // map they alone held together falls apart into maps of their own, each
  // held where it is.
  void Remove(const std::vector<int>& loops, int radius, double significant);
  // Minimizes over the junctions within `radius` hops of `loops`' ends, then
  // over twice as many hops, and so on while a widening lowers the error by
  // more than `significant` (the correction has not died out at the
  // border), until the region stops growing (the whole connected map, or
  // `most_junctions`).
  void Relax(const std::vector<int>& loops, int radius, double significant);
  // Moves map `map` (a lowest chain) rigidly: x ← frame · x for every one
  // of its poses. Its errors do not change.
  void Move(int map, const Pose& frame);
  // Minimizes the error of every map.
  MinimizeResult Optimize();

  // Writes the junctions, their estimates bit for bit, the map's loops and
  // the last trial; Restore reads them into a map of the same graph and
  // chains, which then equals this one. Throws std::runtime_error if the
  // state names a pose or loop the graph does not have, or is not a map
  // (maintained_map_state.cc).
  void Save(ByteWriter* out) const;
  void Restore(ByteReader* in);

 private:
  using Key = std::int64_t;  // ChainOdometry::Key of a junction's pose
  struct Junction {
    int pose;
    Pose x;
    std::vector<int> loops;  // loops of the map at this pose
    int temporary = 0;       // tries holding it
    // The condensed odometry to the next junction of its chain, computed
    // when `next`, that junction's pose, was last seen (-1: never).
    int next = -1;
    Constraint<Pose> to_next;
  };
  using Junctions = std::map<Key, Junction>;

  static bool SameChain(Key a, Key b) { return (a >> 32) == (b >> 32); }
  // Whether `pose` is held: the first pose of its map's lowest chain.
  bool Held(int pose) const;
  // Makes `pose` a junction (placed at its current estimate) if it is not.
  void Insert(int pose, bool temporary);
  // Drops junction `pose` if nothing holds it.
  void Release(int pose);
  // The junctions within `radius` hops of the junctions `seeds`, in key
  // order; no hop layer is added once there are `most_junctions_`.
  std::vector<int> Region(const std::vector<int>& seeds, int radius) const;
  // The condensed odometry from junction `it` to the next of its chain
  // (there must be one), computed again only when that junction changed.
  const Constraint<Pose>& ToNext(typename Junctions::iterator it);
  // Minimizes over `region` with the map's loops and `extra`; writes the
  // result into the junctions and returns it with the errors of `extra` and
  // of the map's loops in the problem. With `relaxed`, the region is first
  // minimized without `extra` and `*relaxed` set to its estimates there
  // (in the order of `region`); Δ is then taken from that minimum, and the
  // minimization with `extra` stops once Δ could not come under
  // `fails_above` (Try).
  MapTrial Minimize(
      const std::vector<int>& region, const std::vector<int>& extra,
      std::vector<Pose>* relaxed = nullptr,
      double fails_above = std::numeric_limits<double>::infinity());
  // Marks `loops` (whose ends are junctions) as loops of the map.
  void Attach(const std::vector<int>& loops);
  // Unmarks `loops` (those in the map); their ends stay junctions.
  void Detach(const std::vector<int>& loops);
  // Each chain's map, by the map's loops between chains, leaving out those
  // between chains `a` and `b` (none if a < 0).
  std::vector<int> Maps(int a, int b) const;

  const PoseGraph<Pose>& graph_;
  const ChainOdometry<Pose>& chains_;
  ConvergenceOptions convergence_;
  int most_junctions_;
  Junctions junctions_;
  // The last Try(): its loops and the estimate it found, until the map
  // changes otherwise.
  struct KeptTrial {
    std::vector<int> loops;
    int radius;
    std::vector<std::pair<int, Pose>> estimate;
  };
  std::unique_ptr<KeptTrial> last_trial_;
  std::vector<bool> in_map_;  // by graph loop index
  // The map's loops between each pair of chains (lower first), by count.
  std::map<std::pair<int, int>, int> between_;
  std::vector<int> map_of_;  // by chain
  // Minimize's local index of each pose of its problem, -1 for the others.
  std::vector<int> local_;
  // Region's poses reached so far, all false between calls.
  mutable std::vector<bool> reached_;
  int num_loops_ = 0;
};

}  // namespace rrr

#endif  // RRR_SOLVER_MAINTAINED_MAP_H_
