// Where tests and benchmarks find the shared datasets.
#ifndef RRR_CORE_TESTING_DATASET_DIR_H_
#define RRR_CORE_TESTING_DATASET_DIR_H_

#include <cstdlib>
#include <fstream>
#include <optional>
#include <string>
#include <variant>

#include "rrr/io/g2o.h"

namespace rrr::testing {

// RRR_DATASETS if set, else ../shared/datasets beside the source tree
// (RRR_SOURCE_DIR, defined by the build).
inline std::string DatasetDir() {
  const char* env = std::getenv("RRR_DATASETS");
  return env ? env : std::string(RRR_SOURCE_DIR) + "/../shared/datasets";
}

// Bicocca 25b's graph at confidence `level` (e.g. "0.150"), or nothing with
// `missing` saying where it was looked for.
inline std::optional<PoseGraph2> ReadBicocca(const std::string& level,
                                             std::string* missing) {
  const std::string path = DatasetDir() + "/bicocca25b/B25b_" + level + ".g2o";
  if (!std::ifstream(path)) {
    *missing = "Bicocca 25b not found at " + path +
               " (set RRR_DATASETS to the datasets folder)";
    return std::nullopt;
  }
  return std::get<PoseGraph2>(ReadG2o(path).graph);
}

}  // namespace rrr::testing

#endif  // RRR_CORE_TESTING_DATASET_DIR_H_
