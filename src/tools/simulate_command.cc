#include "commands.h"
namespace rrr {
void AddSimulateCommand(CLI::App& app) { app.add_subcommand("simulate", "todo"); }
}  // namespace rrr
