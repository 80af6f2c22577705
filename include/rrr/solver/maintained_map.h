// The map RRR keeps between decisions: odometry and the accepted loops.
#ifndef RRR_SOLVER_MAINTAINED_MAP_H_
#define RRR_SOLVER_MAINTAINED_MAP_H_

#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <vector>

#include "rrr/graph/chain_spans.h"
#include "rrr/graph/odometry_chain.h"
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
};

// Odometry plus a set of accepted loops of a graph, with an estimate near
// the minimum of their error. Only the poses that loops touch (junctions)
// are variables: the odometry between consecutive junctions is one condensed
// edge (OdometryChain), so the cost of every operation depends on the loops
// and junctions it reaches, not on the length of the chain. The estimate of
// any other pose is its optimum given the junctions next to it; poses after
// the last junction follow it by odometry.
//
// Changes are local: Add, Remove and Try minimize over the junctions within
// `radius` hops (along the chain or across a loop of the map) of the loops'
// ends, and no further than the hop layer that brings them to
// `most_junctions`; Optimize minimizes over the whole map. Pose 0 is held
// (the map's frame).
template <class Pose>
class MaintainedMap {
 public:
  // The map of `graph`, one chain whose odometry is `chain`. The graph and
  // the chain must outlive the map; poses may be appended to both (same
  // length) between calls.
  MaintainedMap(const PoseGraph<Pose>& graph, const OdometryChain<Pose>& chain,
                const ConvergenceOptions& convergence, int most_junctions);
  // The map of `graph`, whose poses are the chains `spans` laid end to end
  // (the first from pose 0), each with its odometry in `odometry`
  // (OdometryOf), related only by loops: every chain's first pose is a
  // junction, placed at graph.estimates(). The graph and the odometry must
  // outlive the map; the loops of the map must join the chains (a chain
  // nothing relates to pose 0 has no unique minimum).
  MaintainedMap(const PoseGraph<Pose>& graph,
                const std::vector<ChainSpan>& spans,
                const std::vector<OdometryChain<Pose>>& odometry,
                const ConvergenceOptions& convergence, int most_junctions);

  bool Contains(int loop) const;
  int num_loops() const { return num_loops_; }
  int num_junctions() const { return static_cast<int>(junctions_.size()); }

  // d²_l of graph loop `loop` at the current estimate.
  double LoopChi2(int loop) const;
  // The estimate of pose `pose`.
  Pose Estimate(int pose) const;
  // The estimate of every pose of the graph, up to `threads` poses at a time
  // (the same estimates whatever their number).
  std::vector<Pose> Estimates(int threads = 1) const;

  // What adding `loops` (not in the map) would do. The region is first
  // minimized without them, and that improvement of the estimate is kept;
  // otherwise the map is unchanged until KeepTrial(). With a finite
  // `fails_above`, the minimization with them stops once Δ could not come
  // under it (LocalProblem::Minimize's reach): a trial that cannot pass a
  // gate of `fails_above` is not minimized to the end.
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
  // std::logic_error if the map changed since (another Try, Add, Remove or
  // Optimize).
  void KeepTrial(double significant);
  // Adds `loops` and minimizes near them (Relax).
  void Add(const std::vector<int>& loops, int radius, double significant);
  // Adds `loops` and places every junction at `x` (every pose of the
  // graph), without minimizing: for loops whose minimum `x` is known.
  void AddAt(const std::vector<int>& loops, const std::vector<Pose>& x);
  // Removes `loops` (in the map) and minimizes near their ends (Relax).
  void Remove(const std::vector<int>& loops, int radius, double significant);
  // Minimizes over the junctions within `radius` hops of `loops`' ends, then
  // over twice as many hops, and so on while a widening lowers the error by
  // more than `significant` (the correction has not died out at the
  // border), until the region stops growing (the whole connected map, or
  // `most_junctions`).
  void Relax(const std::vector<int>& loops, int radius, double significant);
  // Minimizes the error of the whole map.
  MinimizeResult Optimize();

  // Writes the junctions, their estimates bit for bit, the map's loops and
  // the last trial; Restore reads them into a map of the same graph and
  // chain, which then equals this one. Throws std::runtime_error if the
  // state names a pose or loop the graph does not have
  // (maintained_map_state.cc).
  void Save(ByteWriter* out) const;
  void Restore(ByteReader* in);

 private:
  struct Junction {
    Pose x;
    std::vector<int> loops;  // loops of the map at this pose
    int temporary = 0;       // tries holding it
    // The condensed odometry to the next junction, computed when `next`,
    // that junction's pose, was last seen (-1: never).
    int next = -1;
    Constraint<Pose> to_next;
  };
  using Junctions = std::map<int, Junction>;

  // Makes `pose` a junction (placed at its current estimate) if it is not.
  void Insert(int pose, bool temporary);
  // Drops junction `pose` if nothing holds it.
  void Release(int pose);
  // The junctions within `radius` hops of the junctions `seeds`, ascending;
  // no hop layer is added once there are `most_junctions_`.
  std::vector<int> Region(const std::vector<int>& seeds, int radius) const;
  // The condensed odometry from junction `it` to the next (there must be
  // one), computed again only when the next junction changed.
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

  // The chain that holds `pose`, by index into chains_ and firsts_.
  int ChainOf(int pose) const;
  bool SameChain(int p, int q) const { return ChainOf(p) == ChainOf(q); }
  // The condensed odometry from pose `i` to pose `j` > i of its chain.
  Constraint<Pose> Between(int i, int j) const;

  const PoseGraph<Pose>& graph_;
  std::vector<const OdometryChain<Pose>*> chains_;
  std::vector<int> firsts_;  // each chain's first pose, ascending
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
  // Minimize's local index of each pose of its problem, -1 for the others.
  std::vector<int> local_;
  int num_loops_ = 0;
};

}  // namespace rrr

#endif  // RRR_SOLVER_MAINTAINED_MAP_H_
