// How far a graph's information matrices are from its errors, from the data.
#ifndef RRR_RRR_MAP_NOISE_SCALE_H_
#define RRR_RRR_MAP_NOISE_SCALE_H_

#include <cstdint>
#include <ext/pb_ds/assoc_container.hpp>
#include <ext/pb_ds/tree_policy.hpp>
#include <functional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "rrr/io/byte_stream.h"

namespace rrr {

// The noise scale s: the factor by which the covariances of the edges must
// be multiplied for their errors to be χ²-distributed as the gates assume
// (s = 1: the information matrices are right; s < 1: they are too small).
// One model: the a-posteriori variance factor of the accepted map, taken
// robustly as a median over its degrees of freedom, with a prior that
// weighs as much as kPriorLinks accepted links:
//  - each accepted cluster of n links gives its error per degree of freedom
//    n times (one vote per link): Δ/dof when it is accepted and, at each
//    minimum of the whole map, its error there times max(1, map error /
//    loops' error) (the odometry bends to the loops and takes the rest of
//    the error; with the factor the value for right information is near 1).
//    A median, so a minority of wrongly accepted links cannot move it.
//  - the prior is the information matrices as given (s = 1) unless single
//    loops show them too loose: each loop minimized alone with the odometry
//    (e dof) gives D²/e; the kLoopQuantile-quantile over the loops that
//    arrived by a pose, divided by the same quantile of χ²_e/e, when it is
//    under 1. Low and capped because early in a run most candidates can be
//    false and the information as given is the only other evidence: a false
//    stream never widens the gates beyond it. A loop whose measurement
//    departs from the odometry between its ends by kMostPlausibleDrift of
//    the way travelled or more samples nothing: no odometry errs by that
//    much, so it is false (or joins poses the odometry cannot relate) and
//    says nothing of the noise. The test uses no information matrix.
// While few links are accepted the prior decides; as they accumulate the
// map's own errors take over, without a switch. The prior is kept per pose
// (the loops that arrived before each pose), so a decision made as of a
// pose does not depend on when it is made.
class NoiseScaleEstimate {
 public:
  // The prior rests on a 5 % quantile: at least one candidate in twenty
  // must be a true loop for it to be the true loops' scale.
  static constexpr double kLoopQuantile = 0.05;
  // Decisions wait for this many loop samples: the 5 % quantile then rests
  // on at least one sample below it.
  static constexpr int kMinLoopSamples = 30;
  // The largest departure of a true loop from the odometry, as a share of
  // the way travelled between its ends, on the outlier-free datasets is
  // 0.48 (smallGrid3D); false loops that undo the way travelled depart by
  // 0.82-1.0.
  static constexpr double kMostPlausibleDrift = 0.5;
  // The prior counts as this many accepted links: the map's errors decide
  // once more links than that agree on them (a revisit of ten links, or
  // ten lone links).
  static constexpr int kPriorLinks = 10;

  // `residual_dim` is e (3 in 2D, 6 in 3D).
  explicit NoiseScaleEstimate(int residual_dim);

  // A loop that arrived when the graph had `arrival` poses, whose minimal
  // error alone with the odometry is `chi2`, whose measurement departs from
  // the odometry between its ends by `departure` (m) over `travelled` (m).
  void AddLoopSample(int arrival, double chi2, double departure,
                     double travelled);
  // Records the prior for every pose index below `poses` (again from the
  // earliest that a sample added since arrived by).
  void RecordUntil(int poses);
  // The first pose index by which kMinLoopSamples loops sampled the prior,
  // or -1 if none yet.
  int FirstPoseWithEnoughLoops() const;
  // The prior at pose index `pose` (1 before any record).
  double PriorAt(int pose) const;
  // The estimate for a decision as of pose index `pose`: the median of the
  // prior (kPriorLinks votes) and the accepted links' values.
  double ValueAt(int pose) const;
  // "loops" (the prior is the median) or "clusters", as of `pose`.
  std::string SourceAt(int pose) const;

  // Cluster `cluster` of `links` links was accepted with error `error` over
  // `links`·e dof; replaces an earlier sample.
  void SetClusterSample(int cluster, double error, int links);
  // Cluster `cluster` left the map.
  void RemoveClusterSample(int cluster);
  struct ClusterSample {
    int cluster;
    double error;
    int links;
  };
  // `samples`, the accepted clusters' errors at the minimum of the whole map,
  // whose error there is `map_chi2`, each taken times max(1, map_chi2 / Σ of
  // their errors).
  void SetClusterSamplesAtMinimum(const std::vector<ClusterSample>& samples,
                                  double map_chi2);

  // Writes the samples; Restore reads them into an estimate of the same
  // residual_dim that has none, which then equals this one. Restore throws
  // std::runtime_error naming the problem if the record cannot be one of a
  // graph of `most_poses` poses whose clusters hold `most_links` loops.
  void Save(ByteWriter* out) const;
  void Restore(ByteReader* in, int most_poses, int most_links);

 private:
  // Values with ranks: (value, owner, copy) in an order-statistics tree.
  using Ranked = std::tuple<double, int, int>;
  using RankedSet =
      __gnu_pbds::tree<Ranked, __gnu_pbds::null_type, std::less<Ranked>,
                       __gnu_pbds::rb_tree_tag,
                       __gnu_pbds::tree_order_statistics_node_update>;
  // The layout Save writes and Restore reads (Self: const
  // NoiseScaleEstimate to write, NoiseScaleEstimate to read); `poses` is
  // the count of pose indices the prior is recorded for.
  template <class Stream, class Self>
  static void Transfer(Stream* io, Self* self, std::int64_t* poses);
  void PutClusterSample(int cluster, double value, int links);
  // The median as ValueAt, and whether it is the prior's.
  std::pair<double, bool> Median(int pose) const;

  int residual_dim_;
  double chi2_quantile_ratio_;  // kLoopQuantile-quantile of χ²_e / e
  // The plausible loops' (arrival, D²/e), in the order they came.
  std::vector<std::pair<int, double>> loops_;
  size_t recorded_loops_ = 0;    // of loops_, those RecordUntil took in
  RankedSet recorded_;           // the samples of the recorded poses, by D²/e
  std::vector<size_t> waiting_;  // the others, as indices into loops_
  std::vector<double> prior_;    // per pose index
  std::vector<int> prior_samples_;  // per pose index, non-decreasing
  // By cluster: (error per dof, links); 0 links if it has no sample.
  std::vector<std::pair<double, int>> clusters_;
  RankedSet votes_;  // (error per dof, cluster, link) of the accepted links
};

}  // namespace rrr

#endif  // RRR_RRR_MAP_NOISE_SCALE_H_
