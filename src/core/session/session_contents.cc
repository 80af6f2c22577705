// A session database read whole, as a graph with the candidates' last
// states (rrr export, rrr verify on a session).
#include <cstdlib>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/session/session_store.h"
#include "session_tables.h"
#include "stamped_waiting_table.h"

namespace rrr {

namespace {

template <class Pose>
SessionContents ReadSessionOf(SqliteDb* db, int version) {
  SessionContents contents;
  contents.procedure = MetaValue(db, "procedure");
  if (version > 1) {
    contents.waiting_by_stamp =
        static_cast<int>(StampedWaitingTable<Pose>(db).Read().size());
  }
  contents.updates = static_cast<int>(ReadUpdates(db).size());
  const std::map<int, LoopState> states = ReadFinalStates(db);
  PoseGraph<Pose> graph;
  Pose last;
  const auto fail = [&](const InputRow<Pose>& row, const std::string& what) {
    db->Fail("input " + std::to_string(row.seq) + ": " + what);
  };
  std::vector<InputRow<Pose>> candidates;
  ForEachInput<Pose>(db, [&](const InputRow<Pose>& row) {
    if (row.kind == kLoop) {
      candidates.push_back(row);
      return;
    }
    if ((row.kind == kFirstKeyframe) != (graph.num_poses() == 0)) {
      fail(row, "the first keyframe must come first, and only once");
    }
    if (graph.num_poses() > 0 && row.pose_id != graph.ids().back() + 1) {
      fail(row, "keyframe " + std::to_string(row.pose_id) +
                    " does not follow keyframe " +
                    std::to_string(graph.ids().back()));
    }
    last = row.kind == kFirstKeyframe ? row.keyframe.odometry_pose
                                      : last * row.measurement;
    graph.AddPose(row.pose_id, last);
    if (row.kind == kKeyframe) {
      const int to = graph.num_poses() - 1;
      graph.AddEdge({to - 1, to, row.measurement, row.information});
    }
  });
  for (const auto& row : candidates) {
    const int a = graph.IndexOf(row.from), b = graph.IndexOf(row.to);
    if (a < 0 || b < 0) {
      ++contents.candidates_waiting;
      continue;
    }
    if (std::abs(a - b) <= 1) fail(row, "a candidate joins no loop");
    graph.AddEdge({a, b, row.measurement, row.information});
    const auto state = states.find(row.candidate);
    contents.loop_states.push_back(state == states.end() ? LoopState::kPending
                                                         : state->second);
  }
  contents.graph = std::move(graph);
  return contents;
}

}  // namespace

SessionContents ReadSession(const std::string& path) {
  if (!std::ifstream(path)) throw SessionError(path, "cannot be opened");
  SqliteDb db(path, false);
  int version = 0;
  return CheckSchema(&db, &version) == 2 ? ReadSessionOf<Pose2>(&db, version)
                                         : ReadSessionOf<Pose3>(&db, version);
}

bool LooksLikeSessionDatabase(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char header[16] = {};
  in.read(header, sizeof(header));
  return in && std::string(header, 15) == "SQLite format 3";
}

}  // namespace rrr
