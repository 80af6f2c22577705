// The subcommands of the rrr program; each registers itself on the app.
#ifndef RRR_TOOLS_COMMANDS_H_
#define RRR_TOOLS_COMMANDS_H_

#include <CLI/CLI.hpp>

namespace rrr {

inline constexpr char kToBagDescription[] =
    "Write a g2o file as a bag of rrr_node's inputs: odometry at the poses' "
    "times, each loop candidate just after its later pose; a graph of "
    "several odometry chains as a fleet's (each robot's odometry on "
    "<robot>/odom, starting again at zero with each of its sessions).";

void AddVerifyCommand(CLI::App& app);
void AddOptimizeCommand(CLI::App& app);
void AddSpoilCommand(CLI::App& app);
void AddSimulateCommand(CLI::App& app);
void AddEvaluateCommand(CLI::App& app);
void AddToBagCommand(CLI::App& app);
// `rrr to-bag`: runs rrr_to_bag (AddToBagCommand) with the same arguments.
void AddToBagForwarding(CLI::App& app);
void AddExportCommand(CLI::App& app);

}  // namespace rrr

#endif  // RRR_TOOLS_COMMANDS_H_
