// rrr verify: batch RRR on a g2o file.
#include <algorithm>
#include <chrono>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "commands.h"
#include "graph_file.h"
#include "output_paths.h"
#include "progress_bar.h"
#include "rrr/graph/disjoint_sets.h"
#include "rrr/io/input_error.h"
#include "rrr/io/symbol_key.h"
#include "rrr/robust/dcs.h"
#include "rrr/robust/gnc_tls.h"
#include "rrr/robust/pcm.h"
#include "rrr/rrr/map/verify_with_map.h"
#include "rrr/rrr/published/batch_verifier.h"
#include "rrr/solver/chain_maps.h"
#include "rrr/solver/pose_graph_solver.h"
#include "session_file.h"

namespace rrr {
namespace {

struct VerifyArgs {
  std::string input, output, report;
  bool strict = false;
  bool trust_region = false;
  std::string procedure = "map";
  std::string method = "rrr";
  RrrOptions options;
};

template <class Pose>
nlohmann::json PairList(const PoseGraph<Pose>& graph,
                        const std::vector<int>& loops) {
  nlohmann::json list = nlohmann::json::array();
  for (const int k : loops) {
    const auto& e = graph.loops()[k];
    list.push_back({graph.ids()[e.from], graph.ids()[e.to]});
  }
  return list;
}

// Per candidate, in file order: its pair, state, cluster and the test that
// decided it, with what that test compared.
template <class Pose>
nlohmann::json DecisionList(const PoseGraph<Pose>& graph,
                            const Verdict& verdict) {
  std::vector<bool> accepted(graph.loops().size(), false);
  for (const int k : verdict.accepted) accepted[k] = true;
  nlohmann::json list = nlohmann::json::array();
  for (size_t k = 0; k < graph.loops().size(); ++k) {
    const auto& e = graph.loops()[k];
    const DecisionReason& r = verdict.reasons[k];
    nlohmann::json d = {{"pair", {graph.ids()[e.from], graph.ids()[e.to]}},
                        {"state", accepted[k] ? "accepted" : "rejected"},
                        {"cluster", verdict.cluster_of_loop[k]},
                        {"test", ToString(r.test)}};
    if (r.test != DecisionTest::kNotJudged) {
      d["statistic"] = r.statistic;
      d["gate"] = r.gate;
      d["dof"] = r.dof;
      d["scale"] = r.scale;
      d["pose"] = r.pose < 0 ? -1 : graph.ids()[r.pose];
    }
    if (r.by_cluster >= 0) d["by_cluster"] = r.by_cluster;
    list.push_back(std::move(d));
  }
  return list;
}

// A pose as g2o writes it: x, y, θ or x, y, z, qx, qy, qz, qw.
nlohmann::json PoseNumbers(const Pose2& p) { return {p.x(), p.y(), p.theta()}; }
nlohmann::json PoseNumbers(const Pose3& p) {
  const auto& t = p.translation();
  const auto& q = p.quaternion();
  return {t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()};
}

// The chains of a graph of several, the pairs of them that loops join and the
// maps they make.
template <class Pose>
nlohmann::json ChainsJson(const PoseGraph<Pose>& graph,
                          const ChainMaps<Pose>& chains) {
  const auto& ids = graph.ids();
  nlohmann::json list = nlohmann::json::array();
  for (size_t c = 0; c < chains.chains.size(); ++c) {
    const ChainSpan& span = chains.chains[c];
    nlohmann::json chain = {{"first", ids[span.first]},
                            {"last", ids[span.last]},
                            {"poses", span.size()},
                            {"map", chains.map_of_chain[c]}};
    if (const auto symbol = AsSymbol(ids[span.first])) {
      chain["robot"] = std::string(1, symbol->robot);
      chain["first_index"] = symbol->index;
    }
    list.push_back(std::move(chain));
  }
  nlohmann::json pairs = nlohmann::json::array();
  for (const ChainPair<Pose>& pair : chains.pairs) {
    nlohmann::json p = {{"chains", {pair.first, pair.second}},
                        {"candidates", pair.candidates.size()},
                        {"accepted", PairList(graph, pair.accepted)},
                        {"joined", pair.joined}};
    if (pair.joined) {
      if (!pair.joined_by.empty()) p["joined_by_clusters"] = pair.joined_by;
      p["relative_pose"] = PoseNumbers(pair.relative);
    }
    pairs.push_back(std::move(p));
  }
  nlohmann::json maps = nlohmann::json::array();
  size_t next = 0;
  for (size_t m = 0; m < chains.chains.size(); ++m) {
    nlohmann::json members = nlohmann::json::array();
    for (size_t c = 0; c < chains.chains.size(); ++c) {
      if (chains.map_of_chain[c] == static_cast<int>(m)) members.push_back(c);
    }
    if (members.empty()) continue;
    maps.push_back(
        {{"chains", members},
         {"final_optimization", MinimizeJson(chains.minimized[next++])}});
  }
  return {{"chains", list}, {"chain_pairs", pairs}, {"maps", maps}};
}

// The chains of `graph` as the map procedure left them: a pair is
// joined where a loop between it was accepted; `maintained` has every pose
// in its map's frame, each chain's own frame being that of its first pose's
// estimate in the graph. The maps are then minimized (MinimizeMaps).
template <class Pose>
ChainMaps<Pose> MapsOfChains(const PoseGraph<Pose>& graph,
                             const Verdict& verdict,
                             const std::vector<Pose>& maintained) {
  ChainMaps<Pose> maps;
  maps.chains = ChainSpansOf(graph);
  const int n = static_cast<int>(maps.chains.size());
  // Each chain's frame in its map's: the correction of its first pose.
  std::vector<Pose> frame(n);
  for (int c = 0; c < n; ++c) {
    const int first = maps.chains[c].first;
    frame[c] = maintained[first] * graph.estimates()[first].inverse();
  }
  std::vector<bool> accepted(graph.loops().size(), false);
  for (const int k : verdict.accepted) accepted[k] = true;
  std::map<std::pair<int, int>, int> pair_of;
  for (size_t k = 0; k < graph.loops().size(); ++k) {
    int a = ChainHolding(maps.chains, graph.loops()[k].from);
    int b = ChainHolding(maps.chains, graph.loops()[k].to);
    if (a == b) continue;
    if (a > b) std::swap(a, b);
    const auto [it, added] = pair_of.emplace(
        std::make_pair(a, b), static_cast<int>(maps.pairs.size()));
    if (added) {
      maps.pairs.emplace_back();
      maps.pairs.back().first = a;
      maps.pairs.back().second = b;
      maps.pairs.back().relative = frame[a].inverse() * frame[b];
    }
    ChainPair<Pose>& pair = maps.pairs[it->second];
    pair.candidates.push_back(static_cast<int>(k));
    if (accepted[k]) {
      pair.accepted.push_back(static_cast<int>(k));
      pair.joined = true;
    }
  }
  maps.estimates = maintained;
  for (int c = 0; c < n; ++c) {
    for (int p = maps.chains[c].first; p <= maps.chains[c].last; ++p) {
      maps.estimates[p] = frame[c].inverse() * maintained[p];
    }
  }
  MinimizeMaps(graph, verdict.accepted, &maps);
  return maps;
}

// A recorded session's decisions after Finish(), as the node's ~finish
// makes them, over `graph` (Session::Graph); `*maintained` its estimates.
template <class Pose>
Verdict RecordedVerdict(Session<Pose>* session, PoseGraph<Pose>* graph,
                        MapVerifierStats* stats) {
  session->Update(true);
  std::vector<int> candidate_of_loop, index_of_pose;
  *graph = session->Graph(&candidate_of_loop, &index_of_pose);
  const OnlineVerifier<Pose>& verifier = session->verifier();
  Verdict verdict;
  verdict.cluster_of_loop.assign(graph->loops().size(), -1);
  verdict.reasons.resize(graph->loops().size());
  verdict.clusters.resize(verifier.num_clusters());
  for (size_t k = 0; k < graph->loops().size(); ++k) {
    const int c = candidate_of_loop[k];
    verdict.cluster_of_loop[k] = verifier.cluster_of(c);
    if (verdict.cluster_of_loop[k] >= 0) {
      verdict.clusters[verdict.cluster_of_loop[k]].loops.push_back(k);
    }
    verdict.reasons[k] = verifier.reason(c);
    if (verdict.reasons[k].pose >= 0) {
      verdict.reasons[k].pose = index_of_pose[verdict.reasons[k].pose];
    }
    (verifier.state(c) == LoopState::kAccepted ? verdict.accepted
                                               : verdict.rejected)
        .push_back(static_cast<int>(k));
  }
  if (const auto* map = dynamic_cast<const MapVerifier<Pose>*>(&verifier)) {
    *stats = map->stats();
  }
  return verdict;
}

// Judges `graph` with the method of `args`, or takes the decisions of the
// session `recorded` replayed (its graph then `graph`), and writes the map
// and the report.
template <class Pose>
void Verify(PoseGraph<Pose> graph, const nlohmann::json& input_notes,
            const VerifyArgs& args, Session<Pose>* recorded = nullptr) {
  const auto start = std::chrono::steady_clock::now();
  PoseGraphSolver<Pose> solver(graph, args.options.iterations,
                               args.options.steps);
  MinimizeResult final_map;
  Verdict verdict;
  std::vector<Pose> map;
  MapVerifierStats stats;
  nlohmann::json chains_report;
  if (recorded) {
    verdict = RecordedVerdict(recorded, &graph, &stats);
    ChainMaps<Pose> chains = MapsOfChains(graph, verdict, graph.estimates());
    if (chains.chains.size() > 1) chains_report = ChainsJson(graph, chains);
    map = std::move(chains.estimates);
    final_map = chains.minimized.front();
  } else if (args.method == "dcs") {
    verdict = VerifyWithDcs(graph, DcsOptions(), &map, &final_map);
  } else if (args.method == "gnc") {
    verdict = VerifyWithGncTls(graph, GncTlsOptions(), &map, &final_map);
  } else if (args.method == "pcm") {
    ChainMaps<Pose> maps;
    verdict = VerifyWithPcm(graph, PcmOptions(), &maps);
    if (maps.chains.size() > 1) chains_report = ChainsJson(graph, maps);
    map = std::move(maps.estimates);
    final_map = maps.minimized.front();
  } else if (args.options.procedure == Procedure::kMap) {
    // Robots (ids written as GTSAM symbols) move at once; sessions of one
    // robot come one after another.
    const bool robots = !graph.ids().empty() && AsSymbol(graph.ids()[0]);
    std::vector<Pose> maintained;
    verdict = VerifyWithMap(graph, args.options, &maintained, &stats,
                            ArrivalOrder(graph, robots));
    ChainMaps<Pose> chains = MapsOfChains(graph, verdict, maintained);
    if (chains.chains.size() > 1) chains_report = ChainsJson(graph, chains);
    map = std::move(chains.estimates);
    final_map = chains.minimized.front();
  } else {
    ProgressBar bar("rrr: clusters", true);
    verdict =
        VerifyBatch(LoopEnds(graph), solver, args.options,
                    [&bar](int done, int total) { bar.Update(done, total); });
    map = solver.Optimize(verdict.accepted, {}, &final_map);
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();

  if (!args.output.empty()) {
    WriteG2oFile(graph, map, verdict.accepted, args.output);
  }
  nlohmann::json report;
  report["input"] = args.input;
  report["dimension"] = Pose::kTranslationDim;
  report["poses"] = graph.num_poses();
  report["candidates"] = graph.loops().size();
  report.update(input_notes);
  if (!chains_report.is_null()) report.update(chains_report);
  report["clusters"] = verdict.clusters.size();
  report["accepted"] = PairList(graph, verdict.accepted);
  report["rejected"] = PairList(graph, verdict.rejected);
  if (!verdict.reasons.empty()) {
    report["decisions"] = DecisionList(graph, verdict);
  }
  report["seconds"] = seconds;
  report["method"] = args.method;
  report["options"] = {
      {"procedure", ToString(args.options.procedure)},
      {"cluster_window", args.options.cluster_window},
      {"iterations", args.options.iterations},
      {"trust_region", args.options.steps == SolveSteps::kTrustRegion},
      {"alpha", args.options.alpha},
      {"span_gate", args.options.span_gate},
      {"threads", args.options.threads},
      {"noise_scale", args.options.noise_scale},
      {"map_radius", args.options.map_radius},
      {"map_junctions", args.options.map_junctions}};
  report["final_optimization"] = MinimizeJson(final_map);
  if (args.method == "rrr" &&
      (recorded ? dynamic_cast<const MapVerifier<Pose>*>(
                      &recorded->verifier()) != nullptr
                : args.options.procedure == Procedure::kMap)) {
    report["map_procedure"] = {{"own_solves", stats.own_solves},
                               {"trials", stats.trials},
                               {"quick_accepts", stats.quick_accepts},
                               {"reversals", stats.reversals},
                               {"rejudged", stats.rejudged},
                               {"optimizations", stats.optimizations},
                               {"not_converged", stats.not_converged},
                               {"joins", stats.joins},
                               {"join_revisions", stats.join_revisions}};
    report["noise_scale"] = {{"value", stats.noise_scale},
                             {"source", stats.noise_scale_source},
                             {"group", stats.group_noise_scale},
                             {"a_posteriori", stats.a_posteriori_scale}};
  }
  if (!args.report.empty()) {
    std::ofstream out(args.report);
    out << report.dump(1) << "\n";
    if (!out) throw InputError(args.report, 0, "cannot write report");
  }
  std::cout << "candidates " << graph.loops().size() << ", clusters "
            << verdict.clusters.size() << ", accepted "
            << verdict.accepted.size() << ", rejected "
            << verdict.rejected.size() << ", " << seconds << " s\n";
}

}  // namespace

void AddVerifyCommand(CLI::App& app) {
  auto args = std::make_shared<VerifyArgs>();
  CLI::App* cmd = app.add_subcommand(
      "verify",
      "Judge every loop candidate of a g2o file with RRR and print how many "
      "were accepted; write the optimized graph with only the accepted loops "
      "(-o) and a JSON report of every decision (-r).");
  cmd->add_option("input", args->input,
                  "g2o file (2D or 3D), or a session database of rrr_node")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("-w,--window", args->options.cluster_window,
                  "clustering window t in poses (10 for keyframe graphs, 50 "
                  "for Bicocca 25b)")
      ->capture_default_str();
  cmd->add_option("--method", args->method,
                  "rrr (this package; see --procedure), or for comparison "
                  "dcs (dynamic covariance scaling, phi 1), gnc (GNC with a "
                  "truncated least-squares cost, chi-square 0.99) or pcm "
                  "(pairwise consistency maximization, chi-square 0.99)")
      ->capture_default_str()
      ->check(CLI::IsMember({"rrr", "dcs", "gnc", "pcm"}));
  cmd->add_option("--procedure", args->procedure,
                  "decision procedure: published (RRR as in the paper) or "
                  "map (each cluster judged against a maintained map; see "
                  "README)")
      ->capture_default_str()
      ->check(CLI::IsMember({"published", "map"}));
  cmd->add_option("-s,--noise-scale", args->options.noise_scale,
                  "map procedure: every gate is s times the chi-square "
                  "quantile")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--noise-margin", args->options.noise_margin,
                  "map procedure, estimated scale: the gates use this many "
                  "times the estimate")
      ->capture_default_str();
  cmd->add_option("--map-radius", args->options.map_radius,
                  "map procedure: hops around a cluster's ends that a local "
                  "solve minimizes over")
      ->capture_default_str();
  cmd->add_option("--map-junctions", args->options.map_junctions,
                  "map procedure: a local solve stops widening after the hop "
                  "layer that brings it to this many junctions (a decision's "
                  "cost does not grow with the map)")
      ->capture_default_str();
  cmd->add_option("-k,--iterations", args->options.iterations,
                  "Gauss-Newton iterations per consistency test")
      ->capture_default_str();
  cmd->add_option("-a,--alpha", args->options.alpha, "chi-square quantile")
      ->capture_default_str();
  cmd->add_flag("--trust-region", args->trust_region,
                "published procedure: take each test's iterations as "
                "Levenberg-Marquardt steps, which never raise the error, "
                "instead of Gauss-Newton steps");
  cmd->add_flag("--span-gate", args->options.span_gate,
                "gate each solve's total error over the edges its loops span, "
                "not the whole graph (an option beyond the published method)");
  args->options.threads =
      std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  cmd->add_option("-j,--threads", args->options.threads,
                  "consistency solves run at once; the decisions do not "
                  "depend on it (default: the number of cores)")
      ->capture_default_str();
  cmd->add_flag("--strict", args->strict,
                "stop at the first degenerate candidate (a self loop or an "
                "unknown pose), information matrix that is not positive "
                "definite or file without vertices instead of mending it; "
                "keep duplicates and further edges between consecutive "
                "poses");
  cmd->add_option("-o,--output", args->output,
                  "optimized g2o output (not written if not given)");
  cmd->add_option("-r,--report", args->report,
                  "JSON report output (not written if not given)");
  cmd->callback([args] {
    ParseProcedure(args->procedure, &args->options.procedure);
    if (args->trust_region) {
      args->options.steps = SolveSteps::kTrustRegion;
    }
    const std::string problem = args->options.Validate();
    if (!problem.empty()) throw CLI::ValidationError("verify", problem);
    CheckOutputPaths({args->input}, {args->output, args->report});
    // The map procedure and PCM judge a graph of several odometry chains,
    // joined or not; DCS and GNC-TLS weigh every edge of a connected one; the
    // published procedure needs one chain.
    GraphShape shape = GraphShape::kOneChain;
    if ((args->method == "rrr" && args->options.procedure == Procedure::kMap) ||
        args->method == "pcm") {
      shape = GraphShape::kAnyChains;
    } else if (args->method == "dcs" || args->method == "gnc") {
      shape = GraphShape::kConnected;
    }
    // A node's session database is judged as the node judged it: its
    // inputs replayed in their order, then ~finish.
    if (args->method == "rrr" && LooksLikeSessionDatabase(args->input)) {
      WithSessionDatabase(args->input, &args->options, [&](auto& session) {
        Verify(session.Graph(), nlohmann::json::object(), *args, &session);
      });
      return;
    }
    const G2oFile file = LoadGraph(args->input, args->strict, shape);
    const nlohmann::json notes = InputNotes(file);
    std::visit([&](const auto& g) { Verify(g, notes, *args); }, file.graph);
  });
}

}  // namespace rrr
