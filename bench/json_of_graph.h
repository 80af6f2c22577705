// The tail of the benchmark programs that read one g2o file and print one
// JSON object.
#ifndef RRR_BENCH_JSON_OF_GRAPH_H_
#define RRR_BENCH_JSON_OF_GRAPH_H_

#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <variant>

#include "rrr/io/g2o.h"

namespace rrr {

// Reads the g2o file at `path`, calls `run` with its graph (2D or 3D) and
// prints the JSON object it returns on one line; returns 0. On an error,
// prints it to stderr named by `program` and returns 1.
template <class Run>
int PrintJsonOfGraph(const char* program, const std::string& path,
                     const Run& run) {
  try {
    const G2oFile file = ReadG2o(path);
    const nlohmann::json result =
        std::visit([&](const auto& g) { return run(g); }, file.graph);
    std::cout << result.dump() << "\n";
  } catch (const std::exception& e) {
    std::cerr << program << ": error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

}  // namespace rrr

#endif  // RRR_BENCH_JSON_OF_GRAPH_H_
