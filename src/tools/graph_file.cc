#include "graph_file.h"

#include <iostream>
#include <map>

#include "rrr/io/input_error.h"
#include "session_file.h"

namespace rrr {
namespace {

// Skipped candidates listed one by one per reason; the rest are counted.
constexpr int kWarningsPerReason = 20;

}  // namespace

nlohmann::json InputNotes(const G2oFile& file) {
  nlohmann::json skipped = nlohmann::json::object();
  for (const SkippedCandidate& s : file.skipped_candidates) {
    nlohmann::json& entry = skipped[ToString(s.defect)];
    if (entry.is_null()) entry = {{"count", 0}, {"candidates", {}}};
    entry["count"] = entry["count"].get<int>() + 1;
    entry["candidates"].push_back({s.line, s.from, s.to});
  }
  nlohmann::json repaired = nlohmann::json::array();
  for (const RepairedInformation& r : file.repaired_information) {
    repaired.push_back({r.line, r.from, r.to, r.smallest_eigenvalue});
  }
  return {{"skipped_candidates", skipped},
          {"repaired_information", repaired},
          {"poses_from_odometry", file.poses_from_odometry}};
}

nlohmann::json MinimizeJson(const MinimizeResult& result) {
  return {{"iterations", result.iterations},
          {"initial_chi2", result.initial_chi2},
          {"final_chi2", result.final_chi2},
          {"converged", result.converged},
          {"stopped_by", ToString(result.stop)}};
}

G2oFile LoadGraph(const std::string& path, bool strict, GraphShape shape) {
  if (LooksLikeSessionDatabase(path)) {
    G2oFile file;
    WithSessionDatabase(path, nullptr,
                        [&](auto& session) { file.graph = session.Graph(); });
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
  const auto& repaired = file.repaired_information;
  for (size_t k = 0;
       k < repaired.size() && k < static_cast<size_t>(kWarningsPerReason);
       ++k) {
    std::cerr << "rrr: warning: " << path << ":" << repaired[k].line
              << ": information matrix of edge " << repaired[k].from << " -> "
              << repaired[k].to
              << " is not positive definite (smallest eigenvalue "
              << repaired[k].smallest_eigenvalue
              << "): replaced by the nearest positive definite matrix\n";
  }
  if (!repaired.empty()) {
    std::cerr << "rrr: warning: " << path << ": " << repaired.size()
              << " information matrices repaired (--strict stops at the "
                 "first instead)\n";
  }
  if (file.poses_from_odometry) {
    std::cerr << "rrr: warning: " << path
              << ": no vertices: the poses are the ids the edges name, "
                 "placed along the odometry chain (--strict refuses such a "
                 "file)\n";
  }
  const std::string gap = std::visit(
      [&](const auto& g) -> std::string {
        switch (shape) {
          case GraphShape::kOneChain:
            return g.CheckChain();
          case GraphShape::kConnected:
            return g.CheckConnected(AllLoops(g));
          case GraphShape::kAnyChains:
            break;
        }
        return "";
      },
      file.graph);
  if (!gap.empty()) throw InputError(path, 0, gap);
  return file;
}

}  // namespace rrr
