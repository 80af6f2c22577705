// One consistency solve (odometry and every loop, k = 4 Gauss–Newton
// iterations from odometry) of the synthetic datasets, as Google Benchmark
// cases. Datasets come from RRR_DATASETS (default ../shared/datasets beside
// the source tree); a missing one is reported and skipped.
#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include <cstdlib>
#include <iostream>
#include <string>

#include "../src/core/testing/dataset_dir.h"
#include "dataset_or_skip.h"
#include "rrr/io/g2o.h"
#include "rrr/solver/pose_graph_solver.h"

namespace rrr {
namespace {

std::string DatasetPath(const std::string& name) {
  return testing::DatasetDir() + "/synthetic/" + name + ".g2o";
}

template <class Pose>
void SolveAll(benchmark::State& state, const PoseGraph<Pose>& graph) {
  PoseGraphSolver<Pose> solver(graph, 4);
  const std::vector<int> all = AllLoops(graph);
  double chi2 = 0;
  for (auto _ : state) {
    chi2 = solver.Solve(all).total_chi2;
    benchmark::DoNotOptimize(chi2);
  }
  state.counters["chi2"] = chi2;
  state.counters["poses"] = graph.num_poses();
  state.counters["edges"] = graph.odometry().size() + graph.loops().size();
  rusage usage;
  getrusage(RUSAGE_SELF, &usage);
  state.counters["peak_rss_MB"] = usage.ru_maxrss / 1024.0;
}

void SolveDataset(benchmark::State& state, const std::string& name) {
  const std::string path = DatasetPath(name);
  if (!DatasetOrSkip(state, path)) return;
  const G2oFile file = ReadG2o(path);
  std::visit([&state](const auto& g) { SolveAll(state, g); }, file.graph);
}

BENCHMARK_CAPTURE(SolveDataset, manhattan, std::string("manhattanOlson3500"))
    ->Unit(benchmark::kMillisecond)
    ->MinTime(2.0);
BENCHMARK_CAPTURE(SolveDataset, city10000, std::string("city10000"))
    ->Unit(benchmark::kMillisecond)
    ->MinTime(2.0);
BENCHMARK_CAPTURE(SolveDataset, sphere2500, std::string("sphere2500"))
    ->Unit(benchmark::kMillisecond)
    ->MinTime(2.0);

}  // namespace
}  // namespace rrr

BENCHMARK_MAIN();
