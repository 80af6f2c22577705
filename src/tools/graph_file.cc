#include "graph_file.h"

#include <iostream>

#include "rrr/io/input_error.h"

namespace rrr {

AnyPoseGraph LoadGraph(const std::string& path) {
  G2oFile file = ReadG2o(path);
  if (!file.skipped_tags.empty()) {
    std::cerr << "rrr: warning: " << path
              << ": skipped lines with unknown tags: "
              << DescribeSkipped(file.skipped_tags) << "\n";
  }
  const std::string gap =
      std::visit([](const auto& g) { return g.CheckChain(); }, file.graph);
  if (!gap.empty()) throw InputError(path, 0, gap);
  return std::move(file.graph);
}

}  // namespace rrr
