// Guarding a command's inputs from its outputs.
#ifndef RRR_TOOLS_OUTPUT_PATHS_H_
#define RRR_TOOLS_OUTPUT_PATHS_H_

#include <string>
#include <vector>

namespace rrr {

// Checks, before any work, that no output path is an input or another
// output (the same file by any name, symbolic links included) and that each
// output can be written: an existing file must be writable, a new one's
// folder must exist and be writable. Creates nothing. Throws InputError
// naming the path and the problem. An empty path (an optional output not
// asked for) is passed over.
void CheckOutputPaths(const std::vector<std::string>& inputs,
                      const std::vector<std::string>& outputs);

}  // namespace rrr

#endif  // RRR_TOOLS_OUTPUT_PATHS_H_
