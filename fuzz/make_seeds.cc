// Writes the seed corpora of the fuzz targets into DIR/<target>/: a small
// generated world as g2o text, session databases recorded from it (2D and
// 3D, and a fleet of two robots), serialized LoopClosure and Odometry
// messages, and the map procedure's state saved part way. (scripts/fuzz.sh adds
// the first lines of the shared datasets when they are there.)
//
//   make_seeds DIR
#include <nav_msgs/Odometry.h>
#include <ros/serialization.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "../src/core/testing/feed_poses.h"
#include "../src/core/testing/noisy_chain.h"
#include "../src/core/testing/small_ring.h"
#include "../src/ros/msg_conversion.h"
#include "rrr/geometry/pose3.h"
#include "rrr/io/g2o.h"
#include "rrr/rrr/map/map_verifier.h"
#include "rrr/session/fleet_store.h"
#include "rrr/session/session_store.h"
#include "rrr/sim/simulated_world.h"
#include "rrr_slam/LoopClosure.h"

namespace fs = std::filesystem;

namespace {

template <class M>
void WriteMessage(const M& msg, const fs::path& path) {
  std::vector<uint8_t> bytes(ros::serialization::serializationLength(msg));
  ros::serialization::OStream stream(bytes.data(),
                                     static_cast<uint32_t>(bytes.size()));
  ros::serialization::serialize(stream, msg);
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()),
             static_cast<std::streamsize>(bytes.size()));
}

// Records `graph` as rrr_node would: keyframes, candidates after their later
// pose, an update every `update_every` poses, each committed.
template <class Pose>
void WriteSession(const rrr::PoseGraph<Pose>& graph, int update_every,
                  const fs::path& path) {
  fs::remove(path);
  rrr::MapVerifier<Pose> verifier{rrr::RrrOptions()};
  rrr::SessionStore<Pose> store(path.string(), "map");
  std::vector<int> loop_of_pose(graph.num_poses(), -1);
  std::vector<std::vector<int>> loops_at(graph.num_poses());
  for (size_t k = 0; k < graph.loops().size(); ++k) {
    const auto& l = graph.loops()[k];
    loops_at[std::max(l.from, l.to)].push_back(static_cast<int>(k));
  }
  for (int p = 0; p < graph.num_poses(); ++p) {
    rrr::KeyframeRecord<Pose> keyframe;
    keyframe.stamp_ns = 1000000000LL * p;
    keyframe.odometry_pose = graph.estimates()[p];
    if (p == 0) {
      verifier.AddFirstPose(graph.ids()[0], graph.estimates()[0]);
      store.RecordFirstKeyframe(graph.ids()[0], keyframe);
    } else {
      const auto& e = graph.odometry()[p - 1];
      const rrr::PoseId id = verifier.AddOdometry(e.measurement, e.information);
      store.RecordKeyframe(id, keyframe, e.measurement, e.information);
    }
    for (const int k : loops_at[p]) {
      const auto& l = graph.loops()[k];
      const rrr::PoseId a = graph.ids()[l.from], b = graph.ids()[l.to];
      const int number = verifier.AddLoop(a, b, l.measurement, l.information);
      store.RecordCandidate(number, a, b, l.measurement, l.information);
    }
    if ((p + 1) % update_every == 0)
      store.CommitUpdate(false, verifier.Update());
  }
  // A candidate named by stamp, still waiting at the end.
  const auto& first = graph.loops().front();
  store.RecordStampedWaiting(0, 1000000000LL * graph.num_poses(), 0,
                             first.measurement, first.information);
  store.CommitUpdate(true, verifier.Finish());
}

// Records `graph` as rrr_node records a fleet: its first and second halves
// robots a and b side by side, each loop once both its keyframes exist (one
// by stamp), an update every `update_every` rounds.
void WriteFleetSession(const rrr::PoseGraph<rrr::Pose2>& graph,
                       int update_every, const fs::path& path) {
  fs::remove(path);
  rrr::Fleet<rrr::Pose2> fleet({"a", "b"}, rrr::FleetOptions{});
  rrr::FleetStore<rrr::Pose2> store(path.string(), {"a", "b"}, "map");
  const int half = graph.num_poses() / 2;
  for (int k = 0; k < half; ++k) {
    for (int r = 0; r < 2; ++r) {
      rrr::KeyframeRecord<rrr::Pose2> keyframe;
      keyframe.stamp_ns = 1000000000LL * k;
      keyframe.odometry_pose =
          graph.estimates()[r * half].between(graph.estimates()[r * half + k]);
      const auto taken = fleet.AddReading(r, keyframe);
      store.RecordKeyframe(r, keyframe, taken);
    }
    for (const auto& l : graph.loops()) {
      const int ra = l.from / half, rb = l.to / half;
      const int ka = l.from % half, kb = l.to % half;
      if (ra > 1 || rb > 1 || std::max(ka, kb) != k) continue;
      if (ka == 0) {
        const int number = fleet.AddLoopByStamp(ra, 0, rb, 1000000000LL * kb,
                                                l.measurement, l.information);
        store.RecordCandidateByStamp(number, ra, 0, rb, 1000000000LL * kb,
                                     l.measurement, l.information);
      } else {
        const int number =
            fleet.AddLoop(ra, ka, rb, kb, l.measurement, l.information);
        store.RecordCandidate(number, ra, ka, rb, kb, l.measurement,
                              l.information);
      }
    }
    if ((k + 1) % update_every == 0) store.CommitUpdate(false, fleet.Update());
  }
  store.CommitUpdate(true, fleet.Finish());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: make_seeds DIR\n";
    return 2;
  }
  const fs::path dir = argv[1];
  for (const char* target :
       {"g2o_reader", "session_reader", "msg_conversion", "map_state"})
    fs::create_directories(dir / target);

  rrr::WorldOptions options;
  options.poses = 120;
  options.false_loops = 6;
  options.group = 2;
  const rrr::SimulatedWorld world = rrr::SimulateWorld(options);
  const auto& g = world.graph;
  rrr::WriteG2oFile(g, g.estimates(), rrr::AllLoops(g),
                    (dir / "g2o_reader" / "world2d.g2o").string());
  const rrr::PoseGraph<rrr::Pose3> g3 = rrr::testing::NoisyChain<rrr::Pose3>(
      80, {{2, 40}, {5, 60}, {10, 70}, {30, 75}}, 0.01);
  rrr::WriteG2oFile(g3, g3.estimates(), rrr::AllLoops(g3),
                    (dir / "g2o_reader" / "world3d.g2o").string());

  WriteSession(g, 10, dir / "session_reader" / "world2d.db");
  WriteSession(g3, 40, dir / "session_reader" / "world3d.db");
  WriteFleetSession(g, 10, dir / "session_reader" / "fleet2d.db");

  // The map procedure's state part way through SmallRing(), updated after
  // each pose.
  rrr::MapVerifier<rrr::Pose2> saver{rrr::RrrOptions()};
  rrr::testing::FeedPoses(rrr::testing::SmallRing().graph, 0,
                          rrr::testing::kSmallRingSavedPoses, &saver,
                          [&](int) { saver.Update(); });
  std::ofstream(dir / "map_state" / "world2d.state", std::ios::binary)
      << saver.SaveState();

  rrr_slam::LoopClosure loop;
  loop.header.frame_id = "base_link";
  loop.reference = rrr_slam::LoopClosure::BY_ID;
  loop.from_id = 3;
  loop.to_id = 90;
  loop.relative_pose.pose = rrr_ros::ToRos(g.loops()[0].measurement);
  loop.relative_pose.covariance =
      rrr_ros::CovarianceFromInformation<rrr::Pose2>(g.loops()[0].information);
  WriteMessage(loop, dir / "msg_conversion" / "loop_closure.bin");
  nav_msgs::Odometry odometry;
  odometry.header.frame_id = "odom";
  odometry.child_frame_id = "base_link";
  odometry.pose.pose = rrr_ros::ToRos(g3.estimates()[50]);
  for (int i = 0; i < 6; ++i) odometry.pose.covariance[7 * i] = 0.01 * (i + 1);
  WriteMessage(odometry, dir / "msg_conversion" / "odometry.bin");
  return 0;
}
