// A Google Benchmark case's dataset, or the case skipped naming where the
// dataset was looked for.
#ifndef RRR_BENCH_DATASET_OR_SKIP_H_
#define RRR_BENCH_DATASET_OR_SKIP_H_

#include <benchmark/benchmark.h>

#include <fstream>
#include <string>

namespace rrr {

// Whether `path` exists; if not, `state` is skipped with an error naming it
// and RRR_DATASETS (and its loop run empty, as Google Benchmark requires).
inline bool DatasetOrSkip(benchmark::State& state, const std::string& path) {
  if (std::ifstream(path)) return true;
  state.SkipWithError(("dataset not found: " + path +
                       " (set RRR_DATASETS to the datasets "
                       "folder)")
                          .c_str());
  for (auto _ : state) {
  }
  return false;
}

}  // namespace rrr

#endif  // RRR_BENCH_DATASET_OR_SKIP_H_
