#include "rrr/rrr/map/cluster_strain.h"

#include <algorithm>

namespace rrr {

std::vector<std::pair<double, int>> ClustersStrainedAbove(
    const std::vector<MapTrial::LoopStrain>& map_loops,
    const std::vector<int>& cluster_of_loop,
    const std::function<double(int)>& gate_of_cluster, double above) {
  std::vector<std::pair<int, double>> rise_of;  // (cluster, Δd²)
  rise_of.reserve(map_loops.size());
  for (const auto& l : map_loops) {
    rise_of.emplace_back(cluster_of_loop[l.loop], l.after - l.before);
  }
  std::sort(rise_of.begin(), rise_of.end());
  std::vector<std::pair<double, int>> strained;
  for (size_t k = 0; k < rise_of.size();) {
    const int a = rise_of[k].first;
    double sum = 0.0;
    for (; k < rise_of.size() && rise_of[k].first == a; ++k) {
      sum += rise_of[k].second;
    }
    const double strain = sum / gate_of_cluster(a);
    if (strain > above) strained.emplace_back(strain, a);
  }
  std::sort(strained.rbegin(), strained.rend());
  return strained;
}

}  // namespace rrr
