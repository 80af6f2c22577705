#include "run_commands.h"

#include <exception>
#include <iostream>

namespace rrr {

int RunCommands(int argc, char** argv, const std::string& description,
                const std::vector<AddCommand>& commands) {
  try {
    CLI::App app{description};
    app.require_subcommand(1);
    for (const AddCommand add : commands) add(app);
    try {
      app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
      return app.exit(e);
    }
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "rrr: error: " << e.what() << "\n";
  } catch (...) {
    std::cerr << "rrr: error: unknown exception\n";
  }
  return 1;
}

}  // namespace rrr
