// rrr to-bag: runs rrr_to_bag, the program beside rrr that writes bags.
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "commands.h"

namespace rrr {
namespace {

// The path of `program` in the folder of the running executable.
std::string Sibling(const std::string& program) {
  std::vector<char> self(4096);
  const ssize_t n = readlink("/proc/self/exe", self.data(), self.size() - 1);
  if (n <= 0) {
    throw std::runtime_error(std::string("cannot find the running program: ") +
                             std::strerror(errno));
  }
  const std::string path(self.data(), static_cast<size_t>(n));
  return path.substr(0, path.rfind('/') + 1) + program;
}

}  // namespace

void AddToBagForwarding(CLI::App& app) {
  CLI::App* cmd = app.add_subcommand("to-bag", kToBagDescription);
  // Every argument, --help included, is rrr_to_bag's.
  cmd->prefix_command();
  cmd->set_help_flag();
  cmd->callback([cmd] {
    const std::string program = Sibling("rrr_to_bag");
    std::vector<std::string> args = {program, "to-bag"};
    const std::vector<std::string> rest = cmd->remaining();
    args.insert(args.end(), rest.begin(), rest.end());
    std::vector<char*> argv;
    argv.reserve(args.size() + 1);
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    execv(program.c_str(), argv.data());
    throw std::runtime_error("cannot run " + program + ": " +
                             std::strerror(errno));
  });
}

}  // namespace rrr
