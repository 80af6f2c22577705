// rrr optimize: every edge of a g2o file, solved to convergence.
#include <algorithm>
#include <chrono>
#include <fstream>
#include <future>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "graph_file.h"
#include "output_paths.h"
#include "rrr/io/input_error.h"
#include "rrr/solver/chordal_initialization.h"
#include "rrr/solver/pose_graph_solver.h"

namespace rrr {
namespace {

struct OptimizeArgs {
  std::string input, output, report;
  std::string init = "best";
  bool strict = false;
  ConvergenceOptions convergence{10000, 1e-9};
};

// One minimization from a start, and what it took.
template <class Pose>
struct FromStart {
  std::string start;
  std::vector<Pose> map;
  MinimizeResult result;
  double seconds = 0.0;
};

// Minimizes every edge of `graph` from `start` ("odometry" or "chordal").
template <class Pose>
FromStart<Pose> MinimizeFrom(const PoseGraphSolver<Pose>& solver,
                             const PoseGraph<Pose>& graph,
                             const std::vector<int>& all,
                             const std::string& start,
                             const ConvergenceOptions& convergence) {
  const auto begin = std::chrono::steady_clock::now();
  FromStart<Pose> out;
  out.start = start;
  std::vector<Pose> chordal;
  if (start == "chordal") chordal = ChordalInitialization(graph, all);
  out.map = solver.Optimize(all, convergence, &out.result,
                            start == "chordal" ? &chordal : nullptr);
  out.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - begin)
          .count();
  return out;
}

// Returns whether the chosen minimization converged.
template <class Pose>
bool Optimize(const PoseGraph<Pose>& graph, const nlohmann::json& input_notes,
              const OptimizeArgs& args) {
  const auto start = std::chrono::steady_clock::now();
  PoseGraphSolver<Pose> solver(graph, 1);
  const std::vector<int> all = AllLoops(graph);
  // With "best", both starts run side by side (the solver allows it).
  std::vector<std::future<FromStart<Pose>>> pending;
  for (const std::string s : {"odometry", "chordal"}) {
    if (args.init == s || args.init == "best") {
      pending.push_back(std::async(std::launch::async, [&, s] {
        return MinimizeFrom(solver, graph, all, s, args.convergence);
      }));
    }
  }
  std::vector<FromStart<Pose>> runs;
  runs.reserve(pending.size());
  for (auto& run : pending) runs.push_back(run.get());
  // The lowest minimum reached (one that converged before one that did not).
  const auto better = [](const FromStart<Pose>& a, const FromStart<Pose>& b) {
    return std::make_pair(!a.result.converged, a.result.final_chi2) <
           std::make_pair(!b.result.converged, b.result.final_chi2);
  };
  const FromStart<Pose>& chosen =
      *std::min_element(runs.begin(), runs.end(), better);
  const MinimizeResult& result = chosen.result;
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  WriteG2oFile(graph, chosen.map, all, args.output);
  for (const auto& run : runs) {
    std::cout << "from " << run.start << ": chi2 " << run.result.initial_chi2
              << " -> " << run.result.final_chi2 << " after "
              << run.result.iterations << " iterations, "
              << (run.result.converged ? "converged" : "NOT converged") << " ("
              << ToString(run.result.stop) << "), " << run.seconds << " s"
              << (&run == &chosen && runs.size() > 1 ? ", kept" : "") << "\n";
  }
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
    report["init"] = args.init;
    report["start"] = chosen.start;
    report["optimization"] = MinimizeJson(result);
    nlohmann::json starts = nlohmann::json::object();
    for (const auto& run : runs) {
      starts[run.start] = MinimizeJson(run.result);
      starts[run.start]["seconds"] = run.seconds;
    }
    report["starts"] = starts;
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
      "convergence with Levenberg-Marquardt, from the start --init names. "
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
  cmd->add_option("--init", args->init,
                  "start: odometry (the odometry chain composed), chordal "
                  "(chordal relaxation of the rotations, then the "
                  "translations) or best (both; keep the lower minimum)")
      ->capture_default_str()
      ->check(CLI::IsMember({"odometry", "chordal", "best"}));
  cmd->add_option("--max-iterations", args->convergence.max_iterations,
                  "a safety limit: minimizations stop when a step lowers the "
                  "error by less than 1e-9 of it or none can")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_flag("--strict", args->strict,
                "stop at the first degenerate candidate, information matrix "
                "that is not positive definite or file without vertices "
                "instead of mending it");
  cmd->callback([args] {
    CheckOutputPaths({args->input}, {args->output, args->report});
    // Optimization needs no single odometry chain: a pose without odometry
    // to its predecessor starts from its estimate in the file.
    const G2oFile file =
        LoadGraph(args->input, args->strict, GraphShape::kConnected);
    const nlohmann::json notes = InputNotes(file);
    const bool converged = std::visit(
        [&](const auto& g) { return Optimize(g, notes, *args); }, file.graph);
    if (!converged) throw CLI::RuntimeError(3);
  });
}

}  // namespace rrr
