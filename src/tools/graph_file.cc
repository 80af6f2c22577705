#include "graph_file.h"

#include <iostream>
#include <map>

#include "rrr/io/input_error.h"
#include "rrr/session/session_store.h"

namespace rrr {
namespace {

// Skipped candidates listed one by one per reason; the rest are counted.
constexpr int kWarningsPerReason = 20;

}  // namespace

G2oFile LoadGraph(const std::string& path, bool strict) {
  if (LooksLikeSessionDatabase(path)) {
    G2oFile file;
    SessionContents session = ReadSession(path);
    if (session.candidates_waiting > 0) {
      std::cerr << "rrr: warning: " << path << ": "
                << session.candidates_waiting
                << " candidates waiting for a keyframe never recorded left "
                   "out\n";
    }
    if (session.waiting_by_stamp > 0) {
      std::cerr << "rrr: warning: " << path << ": " << session.waiting_by_stamp
                << " candidates waiting for keyframes by stamp left out\n";
    }
    file.graph = std::move(session.graph);
    return file;
  }
  G2oFile file = ReadG2o(path, strict);
  if (!file.skipped_tags.empty()) {
    std::cerr << "rrr: warning: " << path
              << ": skipped lines with unknown tags: "
              << DescribeSkipped(file.skipped_tags) << "\n";
  }
  std::map<std::string, int> reasons;
  for (const SkippedCandidate& s : file.skipped_candidates) {
    if (++reasons[ToString(s.defect)] <= kWarningsPerReason) {
      std::cerr << "rrr: warning: " << path << ":" << s.line << ": candidate "
                << s.from << " -> " << s.to
                << " skipped: " << ToString(s.defect) << "\n";
    }
  }
  if (!reasons.empty()) {
    std::cerr << "rrr: warning: " << path
              << ": skipped candidates: " << DescribeSkipped(reasons)
              << " (--strict stops at the first instead)\n";
  }
  const std::string gap =
      std::visit([](const auto& g) { return g.CheckChain(); }, file.graph);
  if (!gap.empty()) throw InputError(path, 0, gap);
  return file;
}

}  // namespace rrr
