// Why a loop candidate is in its state: the test that decided it last.
#ifndef RRR_RRR_DECISION_REASON_H_
#define RRR_RRR_DECISION_REASON_H_

#include <string>

namespace rrr {

// The tests of the map procedure (doc/rule.md). Each compares an
// error with a gate s·χ²(α, dof).
enum class DecisionTest {
  // Not judged yet, or judged by a procedure that records no reasons.
  kNotJudged,
  // The loop minimized with the odometry alone: its D² (e dof). A loop the
  // odometry refutes on its own cannot be true, whatever the map.
  kAlone,
  // One link of a cluster against the others and the odometry alone (the
  // cluster's own consistency, which no wrong acceptance can have bent):
  // what it brings, Δ(S) − Δ(S without it) (e dof). The worst link goes
  // while it alone exceeds its gate.
  kOwnLink,
  // The cluster's links S against the odometry alone: their minimal error
  // (e·|S| dof), once no single link stands out.
  kOwn,
  // As kOwnLink, against the map: odometry and the accepted loops.
  kMapLink,
  // As kOwn, against the map: Δ, the increase of the map's minimal error
  // that S brings, or their error at the map's estimate, which bounds Δ
  // from above. Accepted iff under the gate (and each link's d²_l under
  // the gate of one: a cluster's sum must not hide a link the map refutes).
  kMap,
  // An accepted cluster set aside for a later one that conflicts with it
  // (RRR's reversal): `statistic` is what it brings to the map with the
  // later one, over its gate; `gate` what the later one brings with it, over
  // its own (RRR's consistency index: of two clusters that conflict, the
  // one less consistent with the rest goes). For the links that joined two
  // maps, set aside for a contradicting set with more evidence (the join
  // rule): `statistic` is their evidence, `gate` that set's (links that
  // agree, minus one).
  kOutweighed,
  // Links between two maps that no join has related yet, which agree with
  // themselves (their least error with both chains' odometry, the maps'
  // relative pose free, e·(n−1) dof): they wait for the join rule, pending.
  kJoin,
  // Links between two maps that were never joined: the revisit they are in
  // never had more evidence than the revisits between the same chains that
  // contradict it together (`statistic`: its evidence, links that agree
  // minus one; `gate`: the evidence of every revisit between the same
  // chains together, at least 1).
  kApart,
};

// "not_judged", "alone", "own_link", "own", "map_link", "map",
// "outweighed", "join" or "apart".
const char* ToString(DecisionTest test);

// The test that put a candidate in its state, with what it compared.
struct DecisionReason {
  DecisionTest test = DecisionTest::kNotJudged;
  double statistic = 0.0;  // the error tested
  double gate = 0.0;       // s·χ²(α, dof); accepted iff statistic < gate
  double scale = 0.0;      // s in force
  int dof = 0;             // degrees of freedom of the gate
  int pose = -1;           // pose index as of which it was decided
  int by_cluster = -1;     // kOutweighed: the cluster it gave way to
};

}  // namespace rrr

#endif  // RRR_RRR_DECISION_REASON_H_
