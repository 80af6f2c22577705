// Loading a graph (g2o file or session database) for a command, with
// warnings on stderr.
#ifndef RRR_TOOLS_GRAPH_FILE_H_
#define RRR_TOOLS_GRAPH_FILE_H_

#include <string>

#include "rrr/io/g2o.h"

namespace rrr {

// Reads `path`, a g2o file or a session database of rrr_node (ReadSession:
// every candidate of the session, whatever its state). For g2o (see ReadG2o
// for `strict`), warns on stderr about skipped tags and each skipped
// candidate (FILE:LINE and the reason), and checks that the odometry chain
// is connected. Throws InputError (SessionError) naming the file
// otherwise.
G2oFile LoadGraph(const std::string& path, bool strict = false);

}  // namespace rrr

#endif  // RRR_TOOLS_GRAPH_FILE_H_
