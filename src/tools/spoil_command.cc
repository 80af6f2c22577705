#include "commands.h"
namespace rrr {
void AddSpoilCommand(CLI::App& app) { app.add_subcommand("spoil", "todo"); }
}  // namespace rrr
