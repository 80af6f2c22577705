// rrr optimize: every edge of a g2o file, solved to convergence.
#include <chrono>
#include <iostream>

#include "commands.h"
#include "graph_file.h"
#include "output_paths.h"
#include "rrr/solver/gauss_newton.h"

namespace rrr {
namespace {

template <class Pose>
void Optimize(const PoseGraph<Pose>& graph, const std::string& output) {
  const auto start = std::chrono::steady_clock::now();
  GaussNewton<Pose> solver(graph, 1);
  const std::vector<int> all = AllLoops(graph);
  int iterations = 0;
  const std::vector<Pose> map = solver.Optimize(all, {}, &iterations);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  WriteG2oFile(graph, map, all, output);
  std::cout << "chi2 " << solver.Evaluate(all, map).total_chi2 << " after "
            << iterations << " iterations, " << seconds << " s\n";
}

}  // namespace

void AddOptimizeCommand(CLI::App& app) {
  auto input = std::make_shared<std::string>();
  auto output = std::make_shared<std::string>();
  CLI::App* cmd = app.add_subcommand(
      "optimize",
      "Optimize a g2o file with all its edges (no verification) to "
      "convergence, starting from its odometry.");
  cmd->add_option("input", *input, "g2o file")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", *output, "optimized g2o output")->required();
  cmd->callback([input, output] {
    CheckOutputPaths({*input}, {*output});
    const AnyPoseGraph graph = LoadGraph(*input).graph;
    std::visit([&](const auto& g) { Optimize(g, *output); }, graph);
  });
}

}  // namespace rrr
