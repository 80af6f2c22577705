// The map procedure over a graph of several odometry chains: sessions of one
// robot, or robots of a fleet, joined only by loop closures.
#ifndef RRR_RRR_CHAINS_VERIFY_CHAINS_H_
#define RRR_RRR_CHAINS_VERIFY_CHAINS_H_

#include <functional>
#include <vector>

#include "rrr/graph/chain_spans.h"
#include "rrr/graph/pose_graph.h"
#include "rrr/rrr/map/map_verifier.h"
#include "rrr/rrr/options.h"
#include "rrr/rrr/verdict.h"
#include "rrr/solver/chain_maps.h"

namespace rrr {

// What VerifyChains decided: the verdict over every loop of the graph, and
// the maps. With one chain, `estimates` is VerifyWithMap's maintained map and
// `minimized` is empty.
template <class Pose>
struct ChainsVerdict : ChainMaps<Pose> {
  Verdict verdict;
};

// Judges the loops of `graph`, which may hold several odometry chains
// (ChainSpansOf). The loops inside a chain are judged by the map procedure
// on that chain alone, exactly as VerifyWithMap would judge them were it the
// whole graph, and judged again by rule 5 once the chain is joined. The
// loops between two chains are clustered per pair
// (`options.cluster_window` on both ends) and judged by the joining rule:
//  1. Until two chains are joined nothing relates their frames, so no single
//     cluster can be refuted or confirmed by them: one false cluster that
//     agrees with itself (a look-alike place seen by both) is exactly as
//     consistent as a true one. A cluster of at least two links is first
//     held to its own consistency (the links minimized with both chains'
//     maps, the chains' relative pose free: the error they bring, against
//     the gate of e·(n−1) dof; the link that brings most goes while what
//     it brings exceeds one link's gate, sought among the links whose
//     first-order change of the minimum is not under the largest d² there,
//     OwnAgreement). The links that went are refused once the links kept
//     are accepted, or with them if no link stands out among links that do
//     not agree; if the joined map refuses the links kept (rule 3), the
//     links that went are judged next as a cluster of their own.
//  2. Two chains are joined only by two independent clusters that agree
//     (more than a clustering window apart on one chain at least: a revisit
//     the clustering split, or one false group, is one piece of evidence):
//     one placement of the second chain's map in the first's frame fits the
//     links of both, the two maps held as their own loops made them (the
//     least error over the relative pose under the gate of e·(n1+n2−1)
//     dof). Held, the maps cannot bend to absorb the difference between two
//     far-apart false clusters (the odometry's drift between them would);
//     placed, far-apart true revisits agree whatever that drift.
//     Clusters are tried largest first. One false cluster never suffices;
//     two false clusters must agree on the same relative pose. Pairs are
//     judged in order of that evidence (the links of the two clusters that
//     would join them apart), most first, then of their candidates; a pair
//     whose chains are in one map already (through others) is judged by
//     rule 3 against that map, every chain of it in its frame. So a join on
//     less evidence that contradicts joins on more is refused, whichever
//     pair has more candidates.
//  3. Once joined, the other clusters between the two chains are judged
//     against the joined map, the best fitting first: accepted when the
//     error their links bring is under the gate of their dof. Their error
//     at the map's estimate bounds it from above: under the gate, they are
//     accepted at once. A lower bound decides the other way without a
//     trial (test "map_bound"): to first order, a link brings at least its
//     Mahalanobis error at the map's minimum with the covariance of any one
//     path of measurements between its ends (odometry and accepted loops
//     between chains), as the map holds that path and more. Otherwise they
//     are tried as the map procedure tries a cluster: the joined map held
//     as a MaintainedMap of its chains, minimized over the poses within
//     `map_radius` hops of their ends (MaintainedMap::Widen for several
//     links), an upper bound of the whole map's increase; they are
//     accepted, and the map moves to that minimum, if they pass. After
//     each acceptance the map is minimized near the new links. A cluster
//     of one link is held to the map scale, several links to the group
//     scale.
//  4. Joined pairs make joined maps (chains joined through a third are in
//     one map). Every map is minimized with its accepted loops. Loops
//     between chains never joined are refused (test "apart").
//  5. A chain judged alone accepts what its odometry cannot refute: a false
//     revisit that its drift explains bends its map, and the loops between
//     chains that the bent map refutes are refused in its favour. So the
//     clusters inside chains are judged again against each joined map with
//     every accepted loop, as RRR's joint test judges clusters: Δ, how much
//     higher the map's minimum is with a cluster's links than without them
//     (to first order at that minimum, from one factorization of the map:
//     rᵀ(Σ − J H⁻¹ Jᵀ)⁻¹ r), over the gate of its dof at its chain's scale
//     (test "joined_map"). The cluster most over its gate is taken out and
//     the map minimized again, while any is; then one taken out that now
//     fits is put back. The loops between chains that rule 3 refused
//     against the bent map weigh too: a cluster whose coalition (the
//     refused clusters that would fit without it, to first order, two of
//     them separate evidence) outweighs it as RRR's reversal weighs two
//     clusters is taken out (test "outweighed"), the one most outweighed
//     first, while no other is. If any stays out, its chain is judged
//     alone again without it (what it had bent is judged afresh) and rules
//     1–5 run again, until they refute the same loops as before. Rule 5 also
//     weighs a chain's clusters in the map it is first joined to, while pairs
//     remain to be judged: a cluster it refutes there starts the next round
//     at once, so the pairs left are not judged against the map it bent.
// Gates use the larger of the two chains' final noise scales (group scale
// for clusters, map scale for one link). A graph of one chain is judged by
// VerifyWithMap itself. `stats`, if given, sums the chains' statistics.
// Throws std::invalid_argument if `options` do not validate.
template <class Pose>
ChainsVerdict<Pose> VerifyChains(const PoseGraph<Pose>& graph,
                                 const RrrOptions& options,
                                 MapVerifierStats* stats = nullptr);

// One chain judged alone by the map procedure.
template <class Pose>
struct ChainAlone {
  std::vector<int> inside;  // the loops inside it, indices of the graph's
  Verdict verdict;          // over `inside` (its loop k is inside[k])
  std::vector<Pose> map;    // its poses, in its own frame
  MapVerifierStats stats;
};

// Rules 1–5 of VerifyChains over the chains of `graph` (ChainSpansOf), each
// judged alone already (`alone`, by chain, as VerifyChains judges them: every
// loop inside it): the verdict over every loop and the maps, minimized.
// `stats`, if given, sums the chains' statistics.
template <class Pose>
ChainsVerdict<Pose> JudgeChains(const PoseGraph<Pose>& graph,
                                std::vector<ChainAlone<Pose>> alone,
                                const RrrOptions& options,
                                MapVerifierStats* stats = nullptr);

// Called after two maps are joined with a copy of the verdict so far (the
// pairs judged, map_of_chain as it is, each chain in its own frame), which
// it may change, and the joined map's lowest chain. Returns whether to stop
// there.
template <class Pose>
using AfterJoin = std::function<bool(ChainsVerdict<Pose>*, int)>;

// Rules 1–3 of VerifyChains over the chains of `graph` (ChainSpansOf), each
// judged alone already (`alone`, by chain; a loop pending there is counted
// refused): the verdict over every loop, the pairs and the map each chain is
// in, with `estimates` each chain at its own map in its own frame. Rule 4
// (MinimizeMaps) is left to the caller. `stats`, if given, sums the chains'.
// After each join of two maps but the last pair's, `after_join`, if given,
// is called; if it returns true, its copy of the verdict so far is returned.
template <class Pose>
ChainsVerdict<Pose> JudgeBetweenChains(
    const PoseGraph<Pose>& graph, const std::vector<ChainAlone<Pose>>& alone,
    const RrrOptions& options, MapVerifierStats* stats = nullptr,
    const AfterJoin<Pose>& after_join = nullptr);

}  // namespace rrr

#endif  // RRR_RRR_CHAINS_VERIFY_CHAINS_H_
