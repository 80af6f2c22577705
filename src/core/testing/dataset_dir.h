// Where tests and benchmarks find the shared datasets.
#ifndef RRR_CORE_TESTING_DATASET_DIR_H_
#define RRR_CORE_TESTING_DATASET_DIR_H_

#include <cstdlib>
#include <string>

namespace rrr::testing {

// RRR_DATASETS if set, else ../shared/datasets beside the source tree
// (RRR_SOURCE_DIR, defined by the build).
inline std::string DatasetDir() {
  const char* env = std::getenv("RRR_DATASETS");
  return env ? env : std::string(RRR_SOURCE_DIR) + "/../shared/datasets";
}

}  // namespace rrr::testing

#endif  // RRR_CORE_TESTING_DATASET_DIR_H_
