#include "commands.h"
namespace rrr {
void AddEvaluateCommand(CLI::App& app) { app.add_subcommand("evaluate", "todo"); }
}  // namespace rrr
