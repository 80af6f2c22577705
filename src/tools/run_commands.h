// The main of a command-line program of subcommands.
#ifndef RRR_TOOLS_RUN_COMMANDS_H_
#define RRR_TOOLS_RUN_COMMANDS_H_

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace rrr {

using AddCommand = void (*)(CLI::App& app);

// Parses `argv` as exactly one of the subcommands that `commands` register
// on an app described by `description`, and runs it. Returns the exit
// status: 0; CLI11's, after its message, on a parse error; 1 after
// "rrr: error: " and the message of any exception the command throws.
int RunCommands(int argc, char** argv, const std::string& description,
                const std::vector<AddCommand>& commands);

}  // namespace rrr

#endif  // RRR_TOOLS_RUN_COMMANDS_H_
