// ReadG2o of real and synthetic datasets, as Google Benchmark cases: the
// text a verification reads before it starts. Datasets come from
// RRR_DATASETS (default ../shared/datasets beside the source tree); a
// missing one is reported and skipped.
#include <benchmark/benchmark.h>

#include <fstream>
#include <string>

#include "../src/core/testing/dataset_dir.h"
#include "dataset_or_skip.h"
#include "rrr/io/g2o.h"

namespace rrr {
namespace {

void ReadDataset(benchmark::State& state, const std::string& name) {
  const std::string path = testing::DatasetDir() + "/" + name + ".g2o";
  if (!DatasetOrSkip(state, path)) return;
  int poses = 0;
  for (auto _ : state) {
    const G2oFile file = ReadG2o(path);
    poses = std::visit([](const auto& g) { return g.num_poses(); }, file.graph);
    benchmark::DoNotOptimize(poses);
  }
  state.counters["poses"] = poses;
  state.SetBytesProcessed(
      state.iterations() *
      static_cast<std::int64_t>(
          std::ifstream(path, std::ios::ate | std::ios::binary).tellg()));
}

BENCHMARK_CAPTURE(ReadDataset, bicocca_0_150,
                  std::string("bicocca25b/B25b_0.150"))
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(ReadDataset, city10000, std::string("synthetic/city10000"))
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(ReadDataset, sphere2500, std::string("synthetic/sphere2500"))
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace rrr

BENCHMARK_MAIN();
