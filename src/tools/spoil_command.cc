// rrr spoil: add synthetic false loop closures to a g2o file.
#include <iostream>

#include "commands.h"
#include "graph_file.h"
#include "output_paths.h"
#include "rrr/eval/ground_truth.h"
#include "rrr/io/input_error.h"
#include "rrr/sim/false_loops.h"
#include "rrr/solver/pose_graph_solver.h"

namespace rrr {
namespace {

struct SpoilArgs {
  std::string input, output, truth, reference;
  FalseLoopOptions options;
};

// The poses a false loop must be wrong at: those of `args.reference` (same
// ids as the input), else the input's optimum, solved here.
template <class Pose>
std::vector<Pose> ReferencePoses(const PoseGraph<Pose>& graph,
                                 const SpoilArgs& args) {
  if (args.reference.empty()) {
    PoseGraphSolver<Pose> solver(graph, 1);
    return solver.Optimize(AllLoops(graph), {});
  }
  const AnyPoseGraph loaded =
      LoadGraph(args.reference, false, GraphShape::kAnyChains).graph;
  const auto* reference = std::get_if<PoseGraph<Pose>>(&loaded);
  if (!reference) {
    throw InputError(args.reference, 0,
                     "is not of the input's dimension (" + args.input + ")");
  }
  std::vector<Pose> poses;
  for (int k = 0; k < graph.num_poses(); ++k) {
    const int at = reference->IndexOf(graph.ids()[k]);
    if (at < 0) {
      throw InputError(args.reference, 0,
                       "has no pose " + std::to_string(graph.ids()[k]) +
                           " (a pose of " + args.input + ")");
    }
    poses.push_back(reference->estimates()[at]);
  }
  return poses;
}

template <class Pose>
void Spoil(PoseGraph<Pose> graph, const SpoilArgs& args) {
  const std::vector<Pose> reference = ReferencePoses(graph, args);
  int discarded = 0;
  const std::vector<int> added =
      AddFalseLoops(&graph, args.options, &reference, &discarded);
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
  std::cout << "added " << added.size() << " false loops (" << discarded
            << " draws correct at the "
            << (args.reference.empty() ? "input's optimum" : "reference")
            << " discarded); " << graph.loops().size() << " loop candidates in "
            << args.output << "\n";
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
  cmd->add_flag("--look-alike", args->options.look_alike,
                "look-alike places: poses at least --look-alike-gap apart, "
                "measurement near the identity (translation up to "
                "--look-alike-translation m, rotation up to "
                "--look-alike-rotation rad, uniformly)");
  cmd->add_option("--look-alike-gap", args->options.look_alike_gap,
                  "least pose distance of --look-alike")
      ->capture_default_str();
  cmd->add_option("--look-alike-translation",
                  args->options.look_alike_translation,
                  "largest translation of --look-alike in m (0: none)")
      ->capture_default_str();
  cmd->add_option("--look-alike-rotation", args->options.look_alike_rotation,
                  "largest rotation of --look-alike in rad (0: none)")
      ->capture_default_str();
  cmd->add_option("-g,--group", args->options.group,
                  "groups of G consecutive false loops (i+k, j+k)")
      ->capture_default_str();
  cmd->add_flag("--between-chains", args->options.between_chains,
                "every false loop between two odometry chains (robots or "
                "sessions: a gap in the odometry starts a chain)");
  cmd->add_option("-s,--seed", args->options.seed, "random seed")->required();
  cmd->add_option("-o,--output", args->output, "spoiled g2o output")
      ->required();
  cmd->add_option("-t,--truth", args->truth, "list of the false loops (i j)")
      ->required();
  cmd->add_option("--reference", args->reference,
                  "g2o file of the true poses (e.g. rrr optimize's output for "
                  "the input): a draw correct there within 1 m and 15 deg is "
                  "drawn again (default: the input's optimum, solved here)")
      ->check(CLI::ExistingFile);
  cmd->callback([args] {
    CheckOutputPaths({args->input, args->reference},
                     {args->output, args->truth});
    // Several chains are spoiled as one; the optimum needs them connected.
    AnyPoseGraph graph =
        LoadGraph(args->input, false,
                  args->reference.empty() ? GraphShape::kConnected
                                          : GraphShape::kAnyChains)
            .graph;
    std::visit([&](auto& g) { Spoil(std::move(g), *args); }, graph);
  });
}

}  // namespace rrr
