// A fleet over time, as rrr_node serving several robots keeps it, without
// ROS.
#ifndef RRR_SESSION_FLEET_SESSION_H_
#define RRR_SESSION_FLEET_SESSION_H_

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "rrr/fleet/fleet.h"
#include "rrr/session/fleet_store.h"

namespace rrr {

// A Fleet with its session database: what the fleet takes (keyframes and
// candidates) is recorded as it is taken, each update with its decisions
// (FleetStore), and a session opened again on the database takes the
// recording up (each robot then in a new session). Without a database it is
// the fleet alone. Not thread-safe: one owner calls every method.
template <class Pose>
class FleetSession {
 public:
  using Information = typename Constraint<Pose>::Information;

  // The fleet of `robots` (Fleet's constructor, which throws
  // std::invalid_argument for robots or options it refuses), recorded in
  // the database at `database` (empty: none) once Resume() opened it.
  FleetSession(std::vector<std::string> robots, const FleetOptions& options,
               std::string database);
  ~FleetSession();

  // Opens the database (none: does nothing) and replays its recording into
  // the fleet (FleetStore::Resume). Call it before any input. Throws
  // SessionError naming the file if it cannot be opened or replayed.
  FleetResumeSummary Resume();

  // Fleet::AddReading, with the keyframe it makes recorded.
  typename Fleet<Pose>::Taken AddReading(int robot,
                                         const KeyframeRecord<Pose>& reading);
  // Fleet::AddLoop and Fleet::AddLoopByStamp, with the candidate recorded
  // (a DegenerateCandidate they throw records nothing).
  int AddLoop(int robot_a, std::int64_t id_a, int robot_b, std::int64_t id_b,
              const Pose& z, const Information& information);
  int AddLoopByStamp(int robot_a, std::int64_t stamp_a, int robot_b,
                     std::int64_t stamp_b, const Pose& z,
                     const Information& information);

  // What Update made.
  struct Updated {
    std::vector<DecisionChange> changes;
    // Why the database could not record the update ("" if it did, or if
    // there is none). The session goes on without it.
    std::string store_error;
  };
  // Runs the fleet's Update() (Finish() if `finish`) and records it with the
  // inputs taken since the last one.
  Updated Update(bool finish);

  const Fleet<Pose>& fleet() const { return fleet_; }

 private:
  Fleet<Pose> fleet_;
  const std::string database_;
  const std::string procedure_;              // the name the database records
  std::unique_ptr<FleetStore<Pose>> store_;  // once Resume() opened it
};

}  // namespace rrr

#endif  // RRR_SESSION_FLEET_SESSION_H_
