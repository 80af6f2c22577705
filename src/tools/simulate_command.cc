// rrr simulate: a built-in synthetic world, with its ground truth.
#include <iostream>

#include "commands.h"
#include "output_paths.h"
#include "rrr/eval/ground_truth.h"
#include "rrr/io/g2o.h"
#include "rrr/sim/simulated_world.h"

namespace rrr {

void AddSimulateCommand(CLI::App& app) {
  auto options = std::make_shared<WorldOptions>();
  auto output = std::make_shared<std::string>();
  auto truth = std::make_shared<std::string>();
  auto ground_truth = std::make_shared<std::string>();
  CLI::App* cmd = app.add_subcommand(
      "simulate",
      "Make a synthetic world (a grid city, a ring or a straight road): a "
      "noisy odometry chain, true loops at revisits and random false loops, "
      "with its ground truth.");
  auto layout = std::make_shared<std::string>("grid");
  cmd->add_option("--layout", *layout,
                  "grid (streets of a city), ring (laps of a circle: every "
                  "revisit closes one place) or line (no revisit)")
      ->capture_default_str()
      ->check(CLI::IsMember({"grid", "ring", "line"}));
  cmd->add_option("--ring", options->ring, "ring layout: poses per lap")
      ->capture_default_str();
  cmd->add_option("--poses", options->poses, "number of poses")
      ->capture_default_str();
  cmd->add_option("--false-loops", options->false_loops,
                  "number of false loops")
      ->capture_default_str();
  cmd->add_option("--group", options->group, "false loops come in groups of G")
      ->capture_default_str();
  cmd->add_option("--robots", options->robots,
                  "robots that drive the path in turn, each its own odometry "
                  "chain from the identity, keyed as GTSAM symbols a, b, ...")
      ->capture_default_str();
  cmd->add_option("--loop-probability", options->loop_probability,
                  "chance that a revisit yields a true loop candidate")
      ->capture_default_str();
  cmd->add_option("--loops-per-revisit", options->loops_per_revisit,
                  "earlier visits of the place a revisit is matched with, the "
                  "latest first (each a candidate with that chance)")
      ->capture_default_str();
  cmd->add_option("--seed", options->seed, "random seed")
      ->capture_default_str();
  cmd->add_option("-o,--output", *output, "g2o output")->required();
  cmd->add_option("-t,--truth", *truth, "list of the false loops (i j)")
      ->required();
  cmd->add_option("--ground-truth", *ground_truth,
                  "the true trajectory as g2o (vertices and odometry)")
      ->required();
  cmd->callback([=] {
    ParseLayout(*layout, &options->layout);
    const std::string problem = options->Validate();
    if (!problem.empty()) throw CLI::ValidationError("simulate", problem);
    CheckOutputPaths({}, {*output, *truth, *ground_truth});
    const SimulatedWorld world = SimulateWorld(*options);
    const auto& g = world.graph;
    WriteG2oFile(g, g.estimates(), AllLoops(g), *output);
    WriteG2oFile(g, world.truth, {}, *ground_truth);
    std::vector<LoopKey> keys;
    for (const int k : world.false_loops) {
      keys.emplace_back(g.ids()[g.loops()[k].from], g.ids()[g.loops()[k].to]);
    }
    WriteLoopList(keys, "false loops of the simulated world", *truth);
    std::cout << "simulated " << g.num_poses() << " poses, "
              << g.loops().size() - world.false_loops.size() << " true and "
              << world.false_loops.size() << " false loop candidates\n";
  });
}

}  // namespace rrr
