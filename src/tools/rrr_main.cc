// rrr: loop-closure verification of pose graphs from the command line.
#include <CLI/CLI.hpp>
#include <exception>
#include <iostream>

#include "commands.h"
#include "rrr/solver/process_memory.h"

namespace {

int Run(int argc, char** argv) {
  CLI::App app{
      "rrr: robust pose-graph back-end. Verifies loop closures with RRR "
      "(Realizing, Reversing, Recovering) and removes the false ones."};
  app.require_subcommand(1);
  rrr::AddVerifyCommand(app);
  rrr::AddOptimizeCommand(app);
  rrr::AddSpoilCommand(app);
  rrr::AddSimulateCommand(app);
  rrr::AddEvaluateCommand(app);
  rrr::AddToBagCommand(app);
  rrr::AddExportCommand(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (!rrr::KeepFreedMemory()) {
    std::cerr << "rrr: warning: the allocator keeps no freed memory; large "
                 "graphs verify slower\n";
  }
  try {
    return Run(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "rrr: error: " << e.what() << "\n";
  } catch (...) {
    std::cerr << "rrr: error: unknown exception\n";
  }
  return 1;
}
