#include "rrr/eval/ground_truth.h"

#include <algorithm>
#include <cmath>
#include <fstream>

#include "rrr/io/input_error.h"
#include "rrr/io/text_fields.h"

namespace rrr {
namespace {

// Calls `f(fields)` for each non-comment line of `path`.
template <class F>
void ForEachLine(const std::string& path, bool commas, F f) {
  std::ifstream in(path);
  if (!in) throw InputError(path, 0, "cannot open file");
  std::string text;
  int line = 0;
  while (std::getline(in, text)) {
    const TextFields fields(text, path, ++line, commas);
    if (!fields.IsComment()) f(fields);
  }
}

}  // namespace

std::vector<double> ReadTimestamps(const std::string& path) {
  std::vector<double> times;
  ForEachLine(path, false, [&](const TextFields& f) {
    f.ExpectCount(1, "a time stamp line");
    times.push_back(f.Number(0));
  });
  return times;
}

std::vector<std::pair<double, Pose2>> ReadStampedPoses(
    const std::string& path) {
  std::vector<std::pair<double, Pose2>> poses;
  ForEachLine(path, true, [&](const TextFields& f) {
    f.ExpectCount(4, "a 'time, x, y, theta' line");
    poses.emplace_back(f.Number(0),
                       Pose2(f.Number(1), f.Number(2), f.Number(3)));
  });
  std::stable_sort(
      poses.begin(), poses.end(),
      [](const auto& a, const auto& b) { return a.first < b.first; });
  return poses;
}

std::vector<int> AssociateByTime(const std::vector<double>& times,
                                 const std::vector<double>& reference,
                                 double max_dt) {
  std::vector<int> match(times.size(), -1);
  for (size_t k = 0; k < times.size(); ++k) {
    const auto it =
        std::lower_bound(reference.begin(), reference.end(), times[k]);
    int best = -1;
    double best_dt = max_dt;
    for (const auto c : {it - 1, it}) {
      if (c < reference.begin() || c >= reference.end()) continue;
      const double dt = std::abs(*c - times[k]);
      if (dt <= best_dt) {
        best_dt = dt;
        best = static_cast<int>(c - reference.begin());
      }
    }
    match[k] = best;
  }
  return match;
}

std::map<LoopKey, LoopLabel> ReadLoopLabels(const std::string& path,
                                            const std::string& level) {
  std::map<LoopKey, LoopLabel> labels;
  const double wanted = std::stod(level);
  ForEachLine(path, false, [&](const TextFields& f) {
    f.ExpectAtLeast(8, "a label line");
    if (std::abs(f.Number(0) - wanted) > 1e-9) return;
    const bool metric = f.Number(3) != 0;
    const bool grey = f.Number(7) != 0;
    labels[{f.Integer(1), f.Integer(2)}] = LoopLabel{metric || grey, metric};
  });
  if (labels.empty()) throw InputError(path, 0, "no labels for level " + level);
  return labels;
}

std::set<LoopKey> ReadLoopList(const std::string& path) {
  std::set<LoopKey> loops;
  ForEachLine(path, false, [&](const TextFields& f) {
    f.ExpectCount(2, "a loop line 'i j'");
    loops.insert({f.Integer(0), f.Integer(1)});
  });
  return loops;
}

void WriteLoopList(const std::vector<LoopKey>& loops, const std::string& header,
                   const std::string& path) {
  std::ofstream out(path);
  if (!out) throw InputError(path, 0, "cannot open file for writing");
  out << "# " << header << "\n";
  for (const auto& [i, j] : loops) out << i << ' ' << j << '\n';
  out.close();
  if (!out) throw InputError(path, 0, "write failed");
}

}  // namespace rrr
