// rrr: loop-closure verification of pose graphs from the command line.
#include <iostream>

#include "commands.h"
#include "rrr/solver/process_memory.h"
#include "run_commands.h"

int main(int argc, char** argv) {
  if (!rrr::KeepFreedMemory()) {
    std::cerr << "rrr: warning: the allocator keeps no freed memory; large "
                 "graphs verify slower\n";
  }
  return rrr::RunCommands(
      argc, argv,
      "rrr: robust pose-graph back-end. Verifies loop closures with RRR "
      "(Realizing, Reversing, Recovering) and removes the false ones.",
      {rrr::AddVerifyCommand, rrr::AddOptimizeCommand, rrr::AddSpoilCommand,
       rrr::AddSimulateCommand, rrr::AddEvaluateCommand,
       rrr::AddToBagForwarding, rrr::AddExportCommand});
}
