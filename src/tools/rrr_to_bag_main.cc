// rrr_to_bag: rrr's to-bag command (`rrr_to_bag to-bag ...`), a program of
// its own so that rrr loads no ROS library; `rrr to-bag` runs it.
#include "commands.h"
#include "run_commands.h"

int main(int argc, char** argv) {
  return rrr::RunCommands(argc, argv, rrr::kToBagDescription,
                          {rrr::AddToBagCommand});
}
