// Loading a graph (g2o file or session database) for a command, with
// warnings on stderr.
#ifndef RRR_TOOLS_GRAPH_FILE_H_
#define RRR_TOOLS_GRAPH_FILE_H_

#include <nlohmann/json.hpp>
#include <string>

#include "rrr/io/g2o.h"
#include "rrr/solver/convergence.h"

namespace rrr {

// Reads `path`, a g2o file or a session database of rrr_node (replayed:
// Session::Graph() with every candidate, whatever its state). For g2o (see
// ParseG2o for `strict`), warns on stderr about skipped tags, each skipped
// candidate and each repaired information matrix (FILE:LINE and the reason),
// and a file without vertices, and checks the graph's shape as `shape` asks.
// Throws InputError (SessionError) naming the file otherwise.
enum class GraphShape {
  kOneChain,   // one odometry chain (PoseGraph::CheckChain)
  kConnected,  // any chains, every pose reached (PoseGraph::CheckConnected)
  kAnyChains,  // any chains, joined or not
};
G2oFile LoadGraph(const std::string& path, bool strict = false,
                  GraphShape shape = GraphShape::kOneChain);

// What reading left out or mended, for a report: "skipped_candidates" by
// reason ({"self_loop": {"count": n, "candidates": [[line, i, j], ...]},
// ...}), "repaired_information" ([[line, i, j, smallest eigenvalue], ...])
// and "poses_from_odometry".
nlohmann::json InputNotes(const G2oFile& file);

// A minimization for a report: "iterations", "initial_chi2", "final_chi2",
// "converged".
nlohmann::json MinimizeJson(const MinimizeResult& result);

}  // namespace rrr

#endif  // RRR_TOOLS_GRAPH_FILE_H_
