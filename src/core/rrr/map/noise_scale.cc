#include "rrr/rrr/map/noise_scale.h"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>

#include "rrr/rrr/chi_square.h"

namespace rrr {

NoiseScaleEstimate::NoiseScaleEstimate(int residual_dim)
    : residual_dim_(residual_dim),
      chi2_quantile_ratio_(ChiSquareQuantile(kLoopQuantile)(residual_dim) /
                           residual_dim) {}

void NoiseScaleEstimate::AddLoopSample(int arrival, double chi2,
                                       double departure, double travelled) {
  if (departure >= kMostPlausibleDrift * travelled) return;
  loops_.emplace_back(arrival, chi2 / residual_dim_);
}

void NoiseScaleEstimate::RecordUntil(int poses) {
  // The prior at pose p counts the samples with arrival <= p: recorded_
  // holds those of the recorded poses, waiting_ (indices into loops_) the
  // others. A sample that arrived by a recorded pose (it came late) has the
  // entries from its arrival on computed again.
  int from = static_cast<int>(prior_.size());
  for (size_t k = recorded_loops_; k < loops_.size(); ++k) {
    from = std::min(from, loops_[k].first);
  }
  const size_t first_new =
      from < static_cast<int>(prior_.size()) ? 0 : recorded_loops_;
  if (first_new == 0) {
    prior_.resize(from);
    prior_samples_.resize(from);
    recorded_.clear();
    waiting_.clear();
  }
  for (size_t k = first_new; k < loops_.size(); ++k) {
    if (loops_[k].first < from) {
      recorded_.insert(Ranked(loops_[k].second, static_cast<int>(k), 0));
    } else {
      waiting_.push_back(k);
    }
  }
  recorded_loops_ = loops_.size();
  std::stable_sort(waiting_.begin(), waiting_.end(), [&](size_t a, size_t b) {
    return loops_[a].first < loops_[b].first;
  });
  auto next = waiting_.begin();
  for (int p = static_cast<int>(prior_.size()); p < poses; ++p) {
    for (; next != waiting_.end() && loops_[*next].first <= p; ++next) {
      recorded_.insert(
          Ranked(loops_[*next].second, static_cast<int>(*next), 0));
    }
    const size_t n = recorded_.size();
    prior_samples_.push_back(static_cast<int>(n));
    if (n == 0) {
      prior_.push_back(1.0);
      continue;
    }
    // The kLoopQuantile-quantile by the nearest lower rank.
    const double quantile = std::get<0>(*recorded_.find_by_order(
        static_cast<size_t>(kLoopQuantile * static_cast<double>(n - 1))));
    prior_.push_back(
        std::min(1.0, std::max(quantile, std::numeric_limits<double>::min()) /
                          chi2_quantile_ratio_));
  }
  waiting_.erase(waiting_.begin(), next);
}

int NoiseScaleEstimate::FirstPoseWithEnoughLoops() const {
  const auto known = std::lower_bound(prior_samples_.begin(),
                                      prior_samples_.end(), kMinLoopSamples);
  return known == prior_samples_.end()
             ? -1
             : static_cast<int>(known - prior_samples_.begin());
}

double NoiseScaleEstimate::PriorAt(int pose) const {
  if (prior_.empty()) return 1.0;
  return prior_[std::min(std::max(pose, 0),
                         static_cast<int>(prior_.size()) - 1)];
}

std::pair<double, bool> NoiseScaleEstimate::Median(int pose) const {
  // The lower median of the votes with kPriorLinks votes of the prior
  // among them: if k votes lie below the prior, the prior's take the
  // ranks k to k + kPriorLinks - 1.
  const double prior = PriorAt(pose);
  const size_t all = votes_.size() + kPriorLinks;
  const size_t middle = (all - 1) / 2;
  const size_t below = votes_.order_of_key(Ranked(prior, -1, -1));
  if (middle < below) {
    return {std::get<0>(*votes_.find_by_order(middle)), false};
  }
  if (middle < below + kPriorLinks) return {prior, true};
  return {std::get<0>(*votes_.find_by_order(middle - kPriorLinks)), false};
}

double NoiseScaleEstimate::ValueAt(int pose) const {
  return std::max(Median(pose).first, std::numeric_limits<double>::min());
}

std::string NoiseScaleEstimate::SourceAt(int pose) const {
  return Median(pose).second ? "loops" : "clusters";
}

void NoiseScaleEstimate::SetClusterSample(int cluster, double error,
                                          int links) {
  PutClusterSample(cluster, std::max(error, 0.0) / (links * residual_dim_),
                   links);
}

void NoiseScaleEstimate::RemoveClusterSample(int cluster) {
  if (cluster >= static_cast<int>(clusters_.size())) return;
  auto& [value, links] = clusters_[cluster];
  for (int k = 0; k < links; ++k) votes_.erase(Ranked(value, cluster, k));
  links = 0;
}

void NoiseScaleEstimate::PutClusterSample(int cluster, double value,
                                          int links) {
  RemoveClusterSample(cluster);
  if (cluster >= static_cast<int>(clusters_.size())) {
    clusters_.resize(cluster + 1, {0.0, 0});
  }
  clusters_[cluster] = {value, links};
  for (int k = 0; k < links; ++k) votes_.insert(Ranked(value, cluster, k));
}

void NoiseScaleEstimate::SetClusterSamplesAtMinimum(
    const std::vector<ClusterSample>& samples, double map_chi2) {
  double loops_chi2 = 0.0;
  for (const ClusterSample& sample : samples) loops_chi2 += sample.error;
  const double map_over_loops =
      loops_chi2 > 0.0 ? std::max(1.0, map_chi2 / loops_chi2) : 1.0;
  for (const ClusterSample& sample : samples) {
    SetClusterSample(sample.cluster, sample.error * map_over_loops,
                     sample.links);
  }
}

template <class Stream, class Self>
void NoiseScaleEstimate::Transfer(Stream* io, Self* self, std::int64_t* poses) {
  io->Size(&self->loops_, 2 * sizeof(double), "loop samples");
  for (auto& [arrival, value] : self->loops_) {
    io->Field(&arrival, "a loop sample's arrival");
    io->Field(&value, "a loop sample");
  }
  io->Field(&self->recorded_loops_, "the loop samples recorded");
  io->Field(poses, "the poses recorded");
  io->Size(&self->clusters_, 2 * sizeof(double), "cluster samples");
  for (auto& [value, links] : self->clusters_) {
    io->Field(&value, "a cluster sample");
    io->Field(&links, "a cluster sample's links");
  }
}

void NoiseScaleEstimate::Save(ByteWriter* out) const {
  std::int64_t poses = static_cast<std::int64_t>(prior_.size());
  Transfer(out, this, &poses);
}

void NoiseScaleEstimate::Restore(ByteReader* in, int most_poses,
                                 int most_links) {
  std::int64_t poses = 0;
  Transfer(in, this, &poses);
  if (recorded_loops_ > loops_.size() || poses < 0 || poses > most_poses) {
    throw std::runtime_error(
        "the noise scale's record of " + std::to_string(poses) +
        " poses does not fit its " + std::to_string(loops_.size()) +
        " samples and a graph of " + std::to_string(most_poses) + " poses");
  }
  for (const auto& [arrival, value] : loops_) {
    if (arrival < 0 || arrival > most_poses) {
      throw std::runtime_error("a loop sample arrived with " +
                               std::to_string(arrival) + " poses");
    }
  }
  // The prior as recorded: RecordUntil over the samples it had taken in.
  std::vector<std::pair<int, double>> all = std::move(loops_);
  loops_.assign(all.begin(), all.begin() + recorded_loops_);
  recorded_loops_ = 0;
  RecordUntil(static_cast<int>(poses));
  loops_ = std::move(all);
  // Each link votes once: checked before any vote is taken in.
  std::int64_t voting = 0;
  for (const auto& [value, links] : clusters_) {
    voting += links;
    if (links < 0 || voting > most_links) {
      throw std::runtime_error("a cluster sample has " + std::to_string(links) +
                               " links (" + std::to_string(most_links) +
                               " links may vote in all)");
    }
  }
  for (size_t c = 0; c < clusters_.size(); ++c) {
    const auto& [value, links] = clusters_[c];
    for (int k = 0; k < links; ++k) {
      votes_.insert(Ranked(value, static_cast<int>(c), k));
    }
  }
}

}  // namespace rrr
