// rrr spoil: add synthetic false loop closures to a g2o file.
#include <iostream>

#include "commands.h"
#include "graph_file.h"
#include "output_paths.h"
#include "rrr/eval/ground_truth.h"
#include "rrr/sim/false_loops.h"

namespace rrr {
namespace {

struct SpoilArgs {
  std::string input, output, truth;
  FalseLoopOptions options;
};

template <class Pose>
void Spoil(PoseGraph<Pose> graph, const SpoilArgs& args) {
  const std::vector<int> added = AddFalseLoops(&graph, args.options);
  WriteG2oFile(graph, graph.estimates(), AllLoops(graph), args.output);
  std::vector<LoopKey> keys;
  for (const int k : added) {
    const auto& e = graph.loops()[k];
    keys.emplace_back(graph.ids()[e.from], graph.ids()[e.to]);
  }
  WriteLoopList(keys,
                "false loops added to " + args.input + " (seed " +
                    std::to_string(args.options.seed) + ")",
                args.truth);
  std::cout << "added " << added.size() << " false loops; "
            << graph.loops().size() << " loop candidates in " << args.output
            << "\n";
}

}  // namespace

void AddSpoilCommand(CLI::App& app) {
  auto args = std::make_shared<SpoilArgs>();
  CLI::App* cmd = app.add_subcommand(
      "spoil",
      "Add false loop closures between random pose pairs (x, y, z ~ N(0, 0.3 "
      "m), angles ~ N(0, 10 deg), information of the first loop) and list "
      "them.");
  cmd->add_option("input", args->input, "g2o file")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("-n,--outliers", args->options.count, "number of false loops")
      ->required();
  cmd->add_flag("--local", args->options.local,
                "second pose within --local-range poses of the first");
  cmd->add_option("--local-range", args->options.local_range,
                  "range of --local in poses")
      ->capture_default_str();
  cmd->add_option("-g,--group", args->options.group,
                  "groups of G consecutive false loops (i+k, j+k)")
      ->capture_default_str();
  cmd->add_option("-s,--seed", args->options.seed, "random seed")->required();
  cmd->add_option("-o,--output", args->output, "spoiled g2o output")
      ->required();
  cmd->add_option("-t,--truth", args->truth, "list of the false loops (i j)")
      ->required();
  cmd->callback([args] {
    CheckOutputPaths({args->input}, {args->output, args->truth});
    AnyPoseGraph graph = LoadGraph(args->input).graph;
    std::visit([&](auto& g) { Spoil(std::move(g), *args); }, graph);
  });
}

}  // namespace rrr
