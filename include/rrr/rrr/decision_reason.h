// Why a loop candidate is in its state: the test that decided it last.
#ifndef RRR_RRR_DECISION_REASON_H_
#define RRR_RRR_DECISION_REASON_H_

#include <string>

namespace rrr {

// The tests of the map procedure (README, "The rule"). Each compares an
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
  // one less consistent with the rest goes). In VerifyChains' rule 5 the
  // later one is a coalition: the clusters between chains refused against
  // the joined map that would fit without this one (`by_cluster`: the one
  // it strains most).
  kOutweighed,
  // The links of the two clusters that joined two odometry chains: their
  // least error with both chains' maps held, the chains' relative pose free
  // (e·(n−1) dof; VerifyChains).
  kJoin,
  // A loop between two chains that no two agreeing clusters joined: nothing
  // relates their frames, so nothing can confirm it (no statistic).
  kApart,
  // A cluster between two chains against their joined map, refused without
  // a trial: a lower bound of Δ (first order: the largest over its links of
  // a link's Mahalanobis error at the map's minimum with the covariance of
  // one path of measurements between its ends, which the map's cannot
  // exceed) is over the gate of its dof (VerifyChains, rule 3).
  kMapBound,
  // A cluster inside a chain against the map that joined its chain with
  // others: Δ, to first order how much higher that map's minimum is with
  // its links than without them (e·|S| dof; VerifyChains, rule 5).
  kJoinedMap,
};

// "not_judged", "alone", "own_link", "own", "map_link", "map",
// "outweighed", "join", "apart", "map_bound" or "joined_map".
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
