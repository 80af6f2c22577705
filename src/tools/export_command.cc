// rrr export: a session database of rrr_node as a g2o file.
#include <iostream>

#include "commands.h"
#include "output_paths.h"
#include "rrr/io/g2o.h"
#include "session_file.h"

namespace rrr {

void AddExportCommand(CLI::App& app) {
  auto input = std::make_shared<std::string>();
  auto output = std::make_shared<std::string>();
  auto with_rejected = std::make_shared<bool>(false);
  CLI::App* cmd = app.add_subcommand(
      "export",
      "Write the session database of rrr_node (its ~database) as a g2o file: "
      "its keyframes at their corrected poses, the odometry edges and the "
      "accepted and pending loop candidates, the decisions its recorded "
      "updates made.");
  cmd->add_option("input", *input, "session database")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", *output, "g2o output")->required();
  cmd->add_flag("--with-rejected", *with_rejected,
                "write the rejected candidates too (e.g. to verify them again "
                "with rrr verify)");
  cmd->callback([input, output, with_rejected] {
    CheckOutputPaths({*input}, {*output});
    // Under the recorded options: the decisions its updates made.
    WithSessionDatabase(*input, nullptr, [&](auto& session) {
      std::vector<int> candidate_of_loop;
      const auto graph = session.Graph(&candidate_of_loop);
      std::vector<int> loops;
      for (size_t k = 0; k < graph.loops().size(); ++k) {
        if (*with_rejected || session.verifier().state(candidate_of_loop[k]) !=
                                  LoopState::kRejected) {
          loops.push_back(static_cast<int>(k));
        }
      }
      WriteG2oFile(graph, graph.estimates(), loops, *output);
      std::cout << *output << ": " << graph.num_poses() << " keyframes of "
                << session.robots().size() << " robots in "
                << session.num_chains() << " sessions, " << loops.size()
                << " of " << graph.loops().size() << " candidates";
      if (session.num_waiting_by_stamp() + session.num_waiting_for_robots() >
          0) {
        std::cout << "; "
                  << session.num_waiting_by_stamp() +
                         session.num_waiting_for_robots()
                  << " candidates still waiting left out";
      }
      std::cout << "\n";
    });
  });
}

}  // namespace rrr
