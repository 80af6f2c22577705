// Ground truth for evaluation: trajectories, time association, loop labels.
#ifndef RRR_EVAL_GROUND_TRUTH_H_
#define RRR_EVAL_GROUND_TRUTH_H_

#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "rrr/geometry/pose2.h"
#include "rrr/graph/pose_graph.h"

namespace rrr {

// A loop candidate named by the ids of its poses, as in the g2o file.
using LoopKey = std::pair<PoseId, PoseId>;

// Whether a candidate links the same place: topologically (the same place,
// Bicocca's "label or grey") and metrically (also an accurate measurement).
struct LoopLabel {
  bool topological = false;
  bool metric = false;
};

// Rules on the error of a measured edge against the true relative pose.
struct LoopTruthRule {
  double max_translation;  // metres
  double max_rotation;     // radians
};
inline constexpr LoopTruthRule kTopologicalRule{4.25, 45.0 * M_PI / 180.0};
inline constexpr LoopTruthRule kMetricRule{1.0, 15.0 * M_PI / 180.0};

// Labels a measurement z of the relative pose between true poses a and b.
template <class Pose>
LoopLabel JudgeLoop(const Pose& z, const Pose& a, const Pose& b) {
  const Pose error = a.between(b).between(z);
  const double t = error.translation().norm(), r = error.angle();
  return {
      t < kTopologicalRule.max_translation && r < kTopologicalRule.max_rotation,
      t < kMetricRule.max_translation && r < kMetricRule.max_rotation};
}

// One time stamp per line (RAWSEEDS-style pose stamps).
std::vector<double> ReadTimestamps(const std::string& path);

// A time-stamped planar trajectory, one "time, x, y, theta" per line
// (commas or spaces), sorted by time on return.
std::vector<std::pair<double, Pose2>> ReadStampedPoses(const std::string& path);

// For each time in `times`, the index of the nearest time in `reference`
// (sorted ascending), or -1 if none is within `max_dt` seconds.
std::vector<int> AssociateByTime(const std::vector<double>& times,
                                 const std::vector<double>& reference,
                                 double max_dt);

// Bicocca's labels_all_levels.txt ("level i j label terr rerr gtdist grey
// maxdt"): the labels of the candidates at `level`. Throws InputError if the
// level has no entry.
std::map<LoopKey, LoopLabel> ReadLoopLabels(const std::string& path,
                                            const std::string& level);

// A list of loops, one "i j" per line; '#' starts a comment line.
std::set<LoopKey> ReadLoopList(const std::string& path);
// Writes `loops` in the format ReadLoopList reads, with a comment header.
void WriteLoopList(const std::vector<LoopKey>& loops, const std::string& header,
                   const std::string& path);

}  // namespace rrr

#endif  // RRR_EVAL_GROUND_TRUTH_H_
