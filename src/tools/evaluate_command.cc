// rrr evaluate: precision, recall and ATE of a verification against truth.
#include <algorithm>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <type_traits>
#include <variant>

#include "commands.h"
#include "output_paths.h"
#include "rrr/eval/ground_truth.h"
#include "rrr/eval/loop_scores.h"
#include "rrr/eval/trajectory_error.h"
#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/io/g2o.h"
#include "rrr/io/input_error.h"

namespace rrr {
namespace {

struct EvaluateArgs {
  std::string report, map, graph, false_loops, labels, level, gt_g2o, gt_csv,
      timestamps, json;
  double max_dt = 0.25;
};

using Positions = std::map<PoseId, Eigen::VectorXd>;

// The JSON report of rrr verify at `path`.
nlohmann::json ReadReport(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, 0, "cannot open file");
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path, 0, std::string("not a JSON report: ") + e.what());
  }
}

// Candidates of the report (read from `path`), each with whether it was
// accepted.
std::vector<std::pair<LoopKey, bool>> ReadDecisions(
    const nlohmann::json& report, const std::string& path) {
  std::vector<std::pair<LoopKey, bool>> out;
  for (const auto& [field, accepted] :
       {std::pair{"accepted", true}, {"rejected", false}}) {
    if (!report.contains(field) || !report[field].is_array()) {
      throw InputError(path, 0,
                       std::string("the report has no '") + field + "' list");
    }
    for (const auto& pair : report[field]) {
      if (!pair.is_array() || pair.size() != 2 ||
          !pair[0].is_number_integer() || !pair[1].is_number_integer()) {
        throw InputError(
            path, 0,
            std::string("'") + field +
                "' holds an entry that is not [i, j]: " + pair.dump());
      }
      out.push_back({{pair[0].get<PoseId>(), pair[1].get<PoseId>()}, accepted});
    }
  }
  return out;
}

// Poses by pose id, planar or spatial.
using PosesById =
    std::variant<std::map<PoseId, Pose2>, std::map<PoseId, Pose3>>;

// The estimates of `graph` by pose id.
PosesById PosesOf(const AnyPoseGraph& graph) {
  return std::visit(
      [](const auto& g) {
        std::map<PoseId, std::decay_t<decltype(g.estimates()[0])>> out;
        for (int k = 0; k < g.num_poses(); ++k) {
          out[g.ids()[k]] = g.estimates()[k];
        }
        return PosesById(std::move(out));
      },
      graph);
}

// The ground-truth trajectory, if one was given.
std::optional<PosesById> ReadTruth(const EvaluateArgs& args) {
  if (!args.gt_g2o.empty()) {
    return PosesOf(ReadG2o(args.gt_g2o).graph);
  }
  if (!args.gt_csv.empty()) {
    if (args.timestamps.empty()) {
      throw CLI::ValidationError("evaluate", "--gt-csv needs --timestamps");
    }
    const auto stamped = ReadStampedPoses(args.gt_csv);
    std::vector<double> gt_times;
    gt_times.reserve(stamped.size());
    for (const auto& s : stamped) gt_times.push_back(s.first);
    const auto match =
        AssociateByTime(ReadTimestamps(args.timestamps), gt_times, args.max_dt);
    std::map<PoseId, Pose2> out;
    for (size_t id = 0; id < match.size(); ++id) {
      if (match[id] >= 0)
        out[static_cast<PoseId>(id)] = stamped[match[id]].second;
    }
    return out;
  }
  return std::nullopt;
}

Positions PositionsOf(const PosesById& poses) {
  Positions out;
  std::visit(
      [&](const auto& by_id) {
        for (const auto& [id, pose] : by_id) out[id] = pose.translation();
      },
      poses);
  return out;
}

// Each loop of the g2o file `graph_path` labelled by JudgeLoop against the
// true poses; throws InputError when a loop's poses have no ground truth or
// the graph and the truth differ in dimension.
std::map<LoopKey, LoopLabel> JudgeByTruth(const std::string& graph_path,
                                          const PosesById& truth) {
  std::map<LoopKey, LoopLabel> out;
  std::visit(
      [&](const auto& g, const auto& poses) {
        using Pose = std::decay_t<decltype(g.estimates()[0])>;
        using TruePose = typename std::decay_t<decltype(poses)>::mapped_type;
        if constexpr (!std::is_same_v<Pose, TruePose>) {
          throw InputError(graph_path, 0,
                           "the graph and the ground truth differ in "
                           "dimension");
        } else {
          for (const auto& e : g.loops()) {
            const LoopKey key{g.ids()[e.from], g.ids()[e.to]};
            const auto a = poses.find(key.first), b = poses.find(key.second);
            if (a == poses.end() || b == poses.end()) {
              throw InputError(graph_path, 0,
                               "no ground truth for candidate " +
                                   std::to_string(key.first) + " " +
                                   std::to_string(key.second));
            }
            out[key] = JudgeLoop(e.measurement, a->second, b->second);
          }
        }
      },
      ReadG2o(graph_path).graph, truth);
  return out;
}

// Precision and recall count a candidate as correct by the first source
// given: the false-loop list, the labels file, or the ground truth; the
// metric rule's figures come from the labels file or, with --graph, from the
// ground truth (a false loop whose measurement happens to be accurate
// passes it), and otherwise equal the first.
void Evaluate(const EvaluateArgs& args) {
  const nlohmann::json verify_report = ReadReport(args.report);
  const auto decisions = ReadDecisions(verify_report, args.report);
  const std::optional<PosesById> truth = ReadTruth(args);

  std::map<LoopKey, LoopLabel> by_truth;
  if (!args.graph.empty()) {
    if (!truth) {
      throw CLI::ValidationError("evaluate",
                                 "--graph needs --gt-g2o or --gt-csv");
    }
    by_truth = JudgeByTruth(args.graph, *truth);
  } else if (args.false_loops.empty() && args.labels.empty()) {
    throw CLI::ValidationError(
        "evaluate",
        "say which loops are correct: --false-loops, --labels with --level, "
        "or --graph with --gt-g2o / --gt-csv");
  }
  const std::set<LoopKey> false_set = args.false_loops.empty()
                                          ? std::set<LoopKey>()
                                          : ReadLoopList(args.false_loops);
  const std::map<LoopKey, LoopLabel> labels =
      args.labels.empty() ? std::map<LoopKey, LoopLabel>()
                          : ReadLoopLabels(args.labels, args.level);
  const auto label_of = [](const std::map<LoopKey, LoopLabel>& from,
                           const LoopKey& key, const std::string& path) {
    const auto it = from.find(key);
    if (it == from.end()) {
      throw InputError(path, 0,
                       "no label for candidate " + std::to_string(key.first) +
                           " " + std::to_string(key.second));
    }
    return it->second;
  };
  std::vector<bool> accepted, topological, metric;
  for (const auto& [key, is_accepted] : decisions) {
    LoopLabel label;
    if (!args.false_loops.empty()) {
      label.topological = label.metric = !false_set.count(key);
    } else if (!args.labels.empty()) {
      label = label_of(labels, key, args.labels);
    } else {
      label = label_of(by_truth, key, args.graph);
    }
    if (!args.graph.empty() && args.labels.empty()) {
      label.metric = label_of(by_truth, key, args.graph).metric;
    }
    accepted.push_back(is_accepted);
    topological.push_back(label.topological);
    metric.push_back(label.metric);
  }
  const LoopScores top = ScoreLoops(accepted, topological);
  const LoopScores met = ScoreLoops(accepted, metric);

  nlohmann::json out;
  out["candidates"] = top.candidates;
  out["accepted"] = top.accepted;
  out["correct_candidates"] = top.correct_candidates;
  out["correct_accepted"] = top.correct_accepted;
  out["precision"] = top.precision();
  out["recall"] = top.recall();
  out["metric_precision"] = met.precision();
  out["metric_recall"] = met.recall();
  std::cout << std::fixed << std::setprecision(3) << "candidates "
            << top.candidates << ", accepted " << top.accepted << " ("
            << top.correct_accepted << " correct of " << top.correct_candidates
            << "), precision " << top.precision() << ", recall " << top.recall()
            << "; metric rule: precision " << met.precision() << ", recall "
            << met.recall();
  if (!args.map.empty()) {
    if (!truth) {
      throw CLI::ValidationError("evaluate", "ATE needs --gt-g2o or --gt-csv");
    }
    const Positions estimate = PositionsOf(PosesOf(ReadG2o(args.map).graph));
    const Positions reference = PositionsOf(*truth);
    // The ATE of the poses with ids in [first, last] of any range given,
    // over their own best alignment; NaN if too few match.
    const auto ate_over =
        [&](const std::vector<std::pair<PoseId, PoseId>>& ranges,
            size_t* poses) {
          std::vector<Eigen::VectorXd> est, ref;
          for (const auto& [id, p] : estimate) {
            const auto it = reference.find(id);
            const bool in = std::any_of(
                ranges.begin(), ranges.end(), [id = id](const auto& r) {
                  return r.first <= id && id <= r.second;
                });
            if (in && it != reference.end() && it->second.size() == p.size()) {
              est.push_back(p);
              ref.push_back(it->second);
            }
          }
          *poses = est.size();
          if (est.empty() || static_cast<int>(est.size()) <= est[0].size()) {
            return std::numeric_limits<double>::quiet_NaN();
          }
          Eigen::MatrixXd e(est[0].size(), est.size()),
              r(est[0].size(), est.size());
          for (size_t k = 0; k < est.size(); ++k) {
            e.col(k) = est[k];
            r.col(k) = ref[k];
          }
          return AbsoluteTrajectoryError(e, r);
        };
    size_t poses = 0;
    const double ate = ate_over({{std::numeric_limits<PoseId>::min(),
                                  std::numeric_limits<PoseId>::max()}},
                                &poses);
    if (poses == 0) {
      throw InputError(args.map, 0, "no pose matches the ground truth");
    }
    out["ate_rmse"] = ate;
    out["ate_poses"] = poses;
    std::cout << "; ATE RMSE " << ate << " m over " << poses << " poses";
    // A report of several chains: each chain (robot or session) and each map
    // the verification joined, aligned on its own.
    const nlohmann::json& report = verify_report;
    if (report.contains("chains") && report.contains("maps")) {
      std::vector<std::pair<PoseId, PoseId>> spans;
      for (const auto& chain : report["chains"]) {
        spans.emplace_back(chain.at("first").get<PoseId>(),
                           chain.at("last").get<PoseId>());
      }
      out["chains"] = nlohmann::json::array();
      for (size_t c = 0; c < spans.size(); ++c) {
        size_t n = 0;
        const double chain_ate = ate_over({spans[c]}, &n);
        out["chains"].push_back(
            {{"chain", c}, {"ate_rmse", chain_ate}, {"ate_poses", n}});
        std::cout << "\nchain " << c << ": ATE RMSE " << chain_ate << " m over "
                  << n << " poses";
      }
      out["maps"] = nlohmann::json::array();
      for (const auto& map : report["maps"]) {
        std::vector<std::pair<PoseId, PoseId>> members;
        for (const auto& c : map.at("chains")) {
          members.push_back(spans.at(c.get<size_t>()));
        }
        size_t n = 0;
        const double map_ate = ate_over(members, &n);
        out["maps"].push_back({{"chains", map.at("chains")},
                               {"ate_rmse", map_ate},
                               {"ate_poses", n}});
        std::cout << "\nmap of chains " << map.at("chains").dump()
                  << ": ATE RMSE " << map_ate << " m over " << n << " poses";
      }
    }
  }
  std::cout << "\n";
  if (!args.json.empty()) {
    std::ofstream f(args.json);
    f << out.dump(1) << "\n";
    if (!f) throw InputError(args.json, 0, "cannot write");
  }
}

}  // namespace

void AddEvaluateCommand(CLI::App& app) {
  auto args = std::make_shared<EvaluateArgs>();
  CLI::App* cmd = app.add_subcommand(
      "evaluate",
      "Precision and recall of a verify report, and the ATE of its map, "
      "against a ground truth.");
  cmd->add_option("report", args->report, "JSON report of rrr verify")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--map", args->map, "optimized g2o of rrr verify (for ATE)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--false-loops", args->false_loops,
                  "list of the false loops (rrr spoil / simulate --truth)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--labels", args->labels,
                  "Bicocca labels_all_levels.txt (label or grey = correct)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--level", args->level,
                  "confidence level of --labels, e.g. 0.150");
  cmd->add_option("--gt-g2o", args->gt_g2o,
                  "reference trajectory as g2o (same ids)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--gt-csv", args->gt_csv,
                  "time-stamped ground truth: t, x, y, theta")
      ->check(CLI::ExistingFile);
  cmd->add_option("--timestamps", args->timestamps, "time of pose k on line k")
      ->check(CLI::ExistingFile);
  cmd->add_option(
         "--max-dt", args->max_dt,
         "largest time difference of an associated ground-truth pose (s)")
      ->capture_default_str();
  cmd->add_option("--graph", args->graph,
                  "the verified input g2o, to judge loops by the ground truth "
                  "(alone, or for the metric rule beside --false-loops)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--json", args->json, "write the figures as JSON too");
  cmd->callback([args] {
    if (!args->labels.empty() && args->level.empty()) {
      throw CLI::ValidationError("evaluate", "--labels needs --level");
    }
    CheckOutputPaths(
        {args->report, args->map, args->false_loops, args->labels, args->gt_g2o,
         args->gt_csv, args->timestamps, args->graph},
        {args->json});
    Evaluate(*args);
  });
}

}  // namespace rrr
