// How far a graph's information matrices are from its errors, from the data.
#ifndef RRR_RRR_MAP_NOISE_SCALE_H_
#define RRR_RRR_MAP_NOISE_SCALE_H_

#include <map>
#include <string>
#include <vector>

#include "rrr/rrr/map/running_quantile.h"

namespace rrr {

// The noise scale s: the factor by which the covariances of the edges must
// be multiplied for their errors to be χ²-distributed as the gates assume
// (s = 1: the information matrices are right; s < 1: they are too small).
// Two robust estimates, each a ratio of observed minimal errors to their
// degrees of freedom:
//  - from the accepted clusters: the median over the clusters now accepted
//    of their error over its degrees of freedom, once kMinClusters are
//    accepted: at first Δ/dof, the increase each one brought to the map's
//    minimal error over the redundancy it added, and whenever the caller
//    has the minimum of the whole map, each cluster's error there (the
//    a-posteriori variance factor; a local trial's Δ overstates it, since
//    it holds the poses beyond its reach). A median, so a minority of wrong
//    acceptances cannot move it. Once in force it stays while any cluster
//    is accepted: falling back to the loops' estimate, which is looser,
//    would let the clusters that leave be judged again under it.
//  - before that, the information matrices as given (s = 1), unless single
//    loops show them too small: each loop minimized alone with the odometry
//    (e degrees of freedom) gives D²/e, and the kLoopQuantile-quantile over
//    the loops sampled so far (the caller chooses which loops sample the
//    noise), divided by the same quantile of χ²_e/e, replaces 1 when it is
//    smaller. A low quantile and never above 1, because early in
//    a run most candidates can be false (nothing has been revisited yet) and
//    odometry can be overconfident over long stretches: it errs towards a
//    small scale, which sets clusters aside rather than accepting false
//    ones, and the clusters' estimate takes over as soon as it can.
class NoiseScaleEstimate {
 public:
  static constexpr int kMinClusters = 10;
  static constexpr double kLoopQuantile = 0.05;

  // `residual_dim` is e (3 in 2D, 6 in 3D).
  explicit NoiseScaleEstimate(int residual_dim);

  // The minimal error of one loop minimized alone with the odometry.
  void AddLoopSample(double chi2);
  // The estimate from the loop samples so far: min(1, quantile ratio); 1
  // while there is none. O(log n) per sample.
  double FromLoops() const { return from_loops_; }
  int num_loop_samples() const { return loops_.size(); }
  int residual_dim() const { return residual_dim_; }

  // Cluster `cluster` was accepted, raising the map's minimal error by
  // `increase` with `dof` degrees of freedom; replaces an earlier sample.
  void SetClusterSample(int cluster, double increase, int dof);
  // Cluster `cluster` left the map.
  void RemoveClusterSample(int cluster);
  // One cluster's error with its degrees of freedom.
  struct ClusterSample {
    int cluster;
    double error;
    int dof;
  };
  // SetClusterSample for each of `samples` (e.g. the accepted clusters'
  // errors at the minimum of the whole map), the estimate updated once.
  void SetClusterSamples(const std::vector<ClusterSample>& samples);
  // SetClusterSamples for `samples`, the accepted clusters' errors at the
  // minimum of the whole map, whose error there is `map_chi2`, each taken
  // times max(1, map_chi2 / Σ of their errors): the loops hold only part of
  // the map's error (the odometry bends to them), and with the factor the
  // median for a map whose information matrices are right is near 1.
  void SetClusterSamplesAtMinimum(std::vector<ClusterSample> samples,
                                  double map_chi2);

  // The clusters' estimate when it is in force, else `from_loops`.
  double Value(double from_loops) const;
  // "clusters" or "loops": where Value() comes from now.
  std::string Source() const;

  // Writes the samples; Restore reads them into an estimate of the same
  // residual_dim that has none, which then equals this one.
  void Save(ByteWriter* out) const;
  void Restore(ByteReader* in);

 private:
  // Sets cluster `cluster`'s error/dof to `value` (replacing its sample).
  void PutClusterSample(int cluster, double value);
  // Takes the loops' estimate from their quantile (O(1)).
  void UpdateFromLoops();
  // Takes the clusters' estimate from their median (O(1)).
  void UpdateFromClusters();

  int residual_dim_;
  double chi2_quantile_ratio_;  // kLoopQuantile-quantile of χ²_e / e
  RunningQuantile loops_{kLoopQuantile};  // of D²/e of the loop samples
  double from_loops_ = 1.0;
  std::map<int, double> clusters_;       // error/dof by cluster
  RunningQuantile cluster_median_{0.5};  // of the values of clusters_
  double from_clusters_ = 0.0;       // 0 while the loops' estimate is in force
  bool clusters_took_over_ = false;  // kMinClusters samples were reached
};

}  // namespace rrr

#endif  // RRR_RRR_MAP_NOISE_SCALE_H_
