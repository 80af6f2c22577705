// rrr optimize: every edge of a g2o file, solved to convergence.
#include <chrono>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "graph_file.h"
#include "output_paths.h"
#include "rrr/io/input_error.h"
#include "rrr/solver/pose_graph_solver.h"

namespace rrr {
namespace {

struct OptimizeArgs {
  std::string input, output, report;
  bool strict = false;
  ConvergenceOptions convergence;
};

// Returns whether the minimization converged.
template <class Pose>
bool Optimize(const PoseGraph<Pose>& graph, const nlohmann::json& input_notes,
              const OptimizeArgs& args) {
  const auto start = std::chrono::steady_clock::now();
  PoseGraphSolver<Pose> solver(graph, 1);
  const std::vector<int> all = AllLoops(graph);
  MinimizeResult result;
  const std::vector<Pose> map = solver.Optimize(all, args.convergence, &result);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  WriteG2oFile(graph, map, all, args.output);
  std::cout << "chi2 " << result.initial_chi2 << " -> " << result.final_chi2
            << " after " << result.iterations << " iterations, "
            << (result.converged ? "converged" : "NOT converged") << ", "
            << seconds << " s\n";
  if (!result.converged) {
    std::cerr << "rrr: warning: " << args.input << ": "
              << (result.solved
                      ? "not converged within " +
                            std::to_string(args.convergence.max_iterations) +
                            " iterations (--max-iterations)"
                      : "the linear system could not be solved")
              << "; " << args.output << " holds the last estimate\n";
  }
  if (!args.report.empty()) {
    nlohmann::json report = input_notes;
    report["input"] = args.input;
    report["dimension"] = Pose::kTranslationDim;
    report["poses"] = graph.num_poses();
    report["edges"] = graph.odometry().size() + graph.loops().size();
    report["optimization"] = MinimizeJson(result);
    report["seconds"] = seconds;
    std::ofstream out(args.report);
    out << report.dump(1) << "\n";
    if (!out) throw InputError(args.report, 0, "cannot write report");
  }
  return result.converged;
}

}  // namespace

void AddOptimizeCommand(CLI::App& app) {
  auto args = std::make_shared<OptimizeArgs>();
  CLI::App* cmd = app.add_subcommand(
      "optimize",
      "Optimize a g2o file with all its edges (no verification) to "
      "convergence with Levenberg-Marquardt, starting from its odometry. "
      "Exits with status 3 if it did not converge (the output then holds the "
      "last estimate).");
  cmd->add_option("input", args->input, "g2o file")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", args->output, "optimized g2o output")
      ->required();
  cmd->add_option("-r,--report", args->report,
                  "JSON report: iterations, initial and final chi2, whether "
                  "it converged, and what reading mended");
  cmd->add_option("--max-iterations", args->convergence.max_iterations,
                  "iteration limit")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_flag("--strict", args->strict,
                "stop at the first degenerate candidate, information matrix "
                "that is not positive definite or file without vertices "
                "instead of mending it");
  cmd->callback([args] {
    std::vector<std::string> outputs{args->output};
    if (!args->report.empty()) outputs.push_back(args->report);
    CheckOutputPaths({args->input}, outputs);
    const G2oFile file = LoadGraph(args->input, args->strict);
    const nlohmann::json notes = InputNotes(file);
    const bool converged = std::visit(
        [&](const auto& g) { return Optimize(g, notes, *args); }, file.graph);
    if (!converged) throw CLI::RuntimeError(3);
  });
}

}  // namespace rrr
