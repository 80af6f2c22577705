// The map procedure over several chains over time, as a fleet's verifier
// node runs it: a g2o file of several odometry chains fed robot by robot
// side by side, one pose of each chain per round (ArrivalOrder), each loop
// right after its later pose, an update after every pose. Prints, as one
// JSON line, the time of the updates (median, 99th percentile, largest), of
// Finish(), the decisions, and whether they equal those of the batch that
// `rrr verify` runs on the same graph in the same order, with its time.
//
//     chains_online FILE.g2o [--window N]
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <variant>
#include <vector>

#include "json_of_graph.h"
#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/io/g2o.h"
#include "rrr/rrr/map/verify_with_map.h"

namespace rrr {
namespace {

using Clock = std::chrono::steady_clock;

double Seconds(Clock::time_point since) {
  return std::chrono::duration<double>(Clock::now() - since).count();
}

// The q-quantile of `values` (nearest rank), 0 if there are none.
double Quantile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const size_t rank = static_cast<size_t>(q * (values.size() - 1) + 0.5);
  return values[rank];
}

template <class Pose>
nlohmann::json Run(const PoseGraph<Pose>& graph, const RrrOptions& options) {
  const std::vector<int> order = ArrivalOrder(graph, true);
  MapVerifier<Pose> verifier(options);
  std::vector<double> updates;
  // Each update's changes are reported when it returns; the time between
  // two reports is one pose's inputs and its update.
  Clock::time_point last = Clock::now();
  const Clock::time_point start = last;
  double finish = 0.0;
  const std::vector<int> loop_of_candidate = FeedInArrivalOrder<Pose>(
      graph, &verifier, 1,
      [&](const std::vector<DecisionChange>&) {
        updates.push_back(Seconds(last));
        last = Clock::now();
      },
      0, order);
  // The last report is Finish()'s.
  finish = updates.back();
  updates.pop_back();
  const double online = Seconds(start);

  const Clock::time_point batch_start = Clock::now();
  const Verdict batch = VerifyWithMap(
      graph, options, static_cast<std::vector<Pose>*>(nullptr), nullptr, order);
  const double batch_seconds = Seconds(batch_start);
  std::vector<int> accepted;
  for (int c = 0; c < verifier.num_candidates(); ++c) {
    if (verifier.state(c) == LoopState::kAccepted) {
      accepted.push_back(loop_of_candidate[c]);
    }
  }
  std::sort(accepted.begin(), accepted.end());
  int maps = 0;
  for (int c = 0; c < verifier.num_chains(); ++c) {
    maps += verifier.MapOfChain(c) == c;
  }
  nlohmann::json out;
  out["chains"] = verifier.num_chains();
  out["maps"] = maps;
  out["candidates"] = verifier.num_candidates();
  out["accepted"] = accepted.size();
  out["updates"] = updates.size();
  out["update_median_ms"] = 1e3 * Quantile(updates, 0.5);
  out["update_p99_ms"] = 1e3 * Quantile(updates, 0.99);
  out["update_max_ms"] = 1e3 * Quantile(updates, 1.0);
  out["finish_s"] = finish;
  out["online_s"] = online;
  out["batch_s"] = batch_seconds;
  out["equal_to_batch"] = accepted == batch.accepted;
  return out;
}

}  // namespace
}  // namespace rrr

int main(int argc, char** argv) {
  const std::string usage = "usage: chains_online FILE.g2o [--window N]\n";
  if (argc < 2) {
    std::cerr << usage;
    return 2;
  }
  rrr::RrrOptions options;
  options.cluster_window = 10;
  for (int k = 2; k < argc; ++k) {
    const std::string flag = argv[k];
    if (flag == "--window" && k + 1 < argc) {
      options.cluster_window = std::atoi(argv[++k]);
    } else {
      std::cerr << usage;
      return 2;
    }
  }
  return rrr::PrintJsonOfGraph("chains_online", argv[1], [&](const auto& g) {
    return rrr::Run(g, options);
  });
}
