// rrr export: a session database of rrr_node as a g2o file.
#include <iostream>

#include "commands.h"
#include "output_paths.h"
#include "rrr/session/session_store.h"

namespace rrr {
namespace {

// The loops to write: every candidate with `with_rejected`, else the
// accepted and the still pending ones.
std::vector<int> LoopsToWrite(const SessionContents& session,
                              bool with_rejected) {
  std::vector<int> loops;
  for (size_t k = 0; k < session.loop_states.size(); ++k) {
    if (with_rejected || session.loop_states[k] != LoopState::kRejected) {
      loops.push_back(static_cast<int>(k));
    }
  }
  return loops;
}

}  // namespace

void AddExportCommand(CLI::App& app) {
  auto input = std::make_shared<std::string>();
  auto output = std::make_shared<std::string>();
  auto with_rejected = std::make_shared<bool>(false);
  CLI::App* cmd = app.add_subcommand(
      "export",
      "Write the session database of rrr_node (its ~database) as a g2o file: "
      "the keyframes (composed odometry), the odometry edges and the accepted "
      "and pending loop candidates.");
  cmd->add_option("input", *input, "session database")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", *output, "g2o output")->required();
  cmd->add_flag("--with-rejected", *with_rejected,
                "write the rejected candidates too (e.g. to verify them again "
                "with rrr verify)");
  cmd->callback([input, output, with_rejected] {
    CheckOutputPaths({*input}, {*output});
    const SessionContents session = ReadSession(*input);
    const std::vector<int> loops = LoopsToWrite(session, *with_rejected);
    std::visit(
        [&](const auto& graph) {
          WriteG2oFile(graph, graph.estimates(), loops, *output);
          std::cout << *output << ": " << graph.num_poses() << " keyframes, "
                    << loops.size() << " of " << graph.loops().size()
                    << " candidates (" << session.updates << " updates, "
                    << session.procedure << " procedure)";
        },
        session.graph);
    if (session.candidates_waiting > 0) {
      std::cout << "; " << session.candidates_waiting
                << " candidates waiting for a keyframe never recorded left out";
    }
    if (session.waiting_by_stamp > 0) {
      std::cout << "; " << session.waiting_by_stamp
                << " candidates waiting for keyframes by stamp left out";
    }
    std::cout << "\n";
  });
}

}  // namespace rrr
