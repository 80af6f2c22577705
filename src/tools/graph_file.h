// Loading a g2o file for a command, with warnings on stderr.
#ifndef RRR_TOOLS_GRAPH_FILE_H_
#define RRR_TOOLS_GRAPH_FILE_H_

#include <string>

#include "rrr/io/g2o.h"

namespace rrr {

// Reads `path`, warns on stderr about skipped tags, and checks that the
// odometry chain is connected. Throws InputError naming the file otherwise.
AnyPoseGraph LoadGraph(const std::string& path);

}  // namespace rrr

#endif  // RRR_TOOLS_GRAPH_FILE_H_
