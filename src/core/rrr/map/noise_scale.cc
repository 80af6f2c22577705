#include "rrr/rrr/map/noise_scale.h"

#include <algorithm>

#include "rrr/rrr/chi_square.h"

namespace rrr {

NoiseScaleEstimate::NoiseScaleEstimate(int residual_dim)
    : residual_dim_(residual_dim),
      chi2_quantile_ratio_(ChiSquareQuantile(kLoopQuantile)(residual_dim) /
                           residual_dim) {}

void NoiseScaleEstimate::AddLoopSample(double chi2) {
  loops_.Add(chi2 / residual_dim_);
  UpdateFromLoops();
}

void NoiseScaleEstimate::UpdateFromLoops() {
  if (loops_.size() == 0) return;
  // The kLoopQuantile-quantile of D²/e over that of χ²_e/e, at most 1.
  from_loops_ =
      std::min(1.0, std::max(loops_.Value(), 1e-12) / chi2_quantile_ratio_);
}

void NoiseScaleEstimate::SetClusterSample(int cluster, double increase,
                                          int dof) {
  SetClusterSamples({{cluster, increase, dof}});
}

void NoiseScaleEstimate::RemoveClusterSample(int cluster) {
  const auto it = clusters_.find(cluster);
  if (it != clusters_.end()) {
    cluster_median_.Remove(it->second);
    clusters_.erase(it);
  }
  UpdateFromClusters();
}

void NoiseScaleEstimate::PutClusterSample(int cluster, double value) {
  const auto [it, added] = clusters_.emplace(cluster, value);
  if (!added) {
    cluster_median_.Remove(it->second);
    it->second = value;
  }
  cluster_median_.Add(value);
}

void NoiseScaleEstimate::SetClusterSamples(
    const std::vector<ClusterSample>& samples) {
  for (const ClusterSample& sample : samples) {
    PutClusterSample(sample.cluster, std::max(sample.error, 0.0) / sample.dof);
  }
  UpdateFromClusters();
}

void NoiseScaleEstimate::SetClusterSamplesAtMinimum(
    std::vector<ClusterSample> samples, double map_chi2) {
  double loops_chi2 = 0.0;
  for (const ClusterSample& sample : samples) loops_chi2 += sample.error;
  if (loops_chi2 > 0.0) {
    const double map_over_loops = std::max(1.0, map_chi2 / loops_chi2);
    for (ClusterSample& sample : samples) sample.error *= map_over_loops;
  }
  SetClusterSamples(samples);
}

void NoiseScaleEstimate::UpdateFromClusters() {
  const int count = static_cast<int>(clusters_.size());
  clusters_took_over_ = clusters_took_over_ || count >= kMinClusters;
  if (count == 0 || !clusters_took_over_) {
    from_clusters_ = 0.0;
    return;
  }
  from_clusters_ = std::max(cluster_median_.Value(), 1e-12);
}

void NoiseScaleEstimate::Save(ByteWriter* out) const {
  loops_.Save(out);
  out->Int(static_cast<std::int64_t>(clusters_.size()));
  for (const auto& [cluster, value] : clusters_) {
    out->Int(cluster);
    out->Double(value);
  }
  out->Int(clusters_took_over_ ? 1 : 0);
}

void NoiseScaleEstimate::Restore(ByteReader* in) {
  loops_.Restore(in);
  UpdateFromLoops();
  const size_t n = in->Count("cluster samples", 2 * sizeof(double));
  for (size_t k = 0; k < n; ++k) {
    const int cluster = static_cast<int>(in->Int("a sample's cluster"));
    PutClusterSample(cluster, in->Double("a cluster sample"));
  }
  clusters_took_over_ = in->Int("whether clusters took over") != 0;
  UpdateFromClusters();
}

double NoiseScaleEstimate::Value(double from_loops) const {
  return from_clusters_ > 0.0 ? from_clusters_ : from_loops;
}

std::string NoiseScaleEstimate::Source() const {
  return from_clusters_ > 0.0 ? "clusters" : "loops";
}

}  // namespace rrr
