// The subcommands of the rrr program; each registers itself on the app.
#ifndef RRR_TOOLS_COMMANDS_H_
#define RRR_TOOLS_COMMANDS_H_

#include <CLI/CLI.hpp>

namespace rrr {

void AddVerifyCommand(CLI::App& app);
void AddOptimizeCommand(CLI::App& app);
void AddSpoilCommand(CLI::App& app);
void AddSimulateCommand(CLI::App& app);
void AddEvaluateCommand(CLI::App& app);
void AddToBagCommand(CLI::App& app);
void AddExportCommand(CLI::App& app);

}  // namespace rrr

#endif  // RRR_TOOLS_COMMANDS_H_
