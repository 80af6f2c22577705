// Writes the seed corpora of the fuzz targets into DIR/<target>/: a small
// generated world as g2o text, session databases recorded from it (2D and
// 3D, and a fleet of two robots, with checkpoints), serialized LoopClosure and
// Odometry messages, and the map procedure's state saved part way.
// (scripts/fuzz.sh adds the first lines of the shared datasets when they are
// there.)
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
#include "rrr/session/session.h"
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

// Records `graph` as rrr_node records `robots` robots (1 or 2): robot r
// drives part r of its poses, side by side, each loop once both its
// keyframes exist (those at a robot's first keyframe by stamp, one more by
// stamp still waiting at the end), an update every `update_every` rounds.
template <class Pose>
void WriteSession(const rrr::PoseGraph<Pose>& graph,
                  const std::vector<std::string>& robots, int update_every,
                  const fs::path& path) {
  fs::remove(path);
  rrr::SessionOptions options;
  options.database = path.string();
  options.checkpoint_keyframes = 50;
  rrr::Session<Pose> session(robots, options, nullptr);
  session.Resume();
  const int n = static_cast<int>(robots.size());
  const int part = graph.num_poses() / n;
  constexpr std::int64_t kSecond = 1000000000;
  for (int k = 0; k < part; ++k) {
    for (int r = 0; r < n; ++r) {
      rrr::KeyframeRecord<Pose> keyframe;
      keyframe.stamp_ns = kSecond * k;
      keyframe.odometry_pose =
          graph.estimates()[r * part].between(graph.estimates()[r * part + k]);
      session.AddReading(r, keyframe);
    }
    for (const auto& l : graph.loops()) {
      const int ra = l.from / part, rb = l.to / part;
      const int ka = l.from % part, kb = l.to % part;
      if (ra >= n || rb >= n || std::max(ka, kb) != k) continue;
      if (ka == 0) {
        session.AddCandidateByStamp(0, ra, 0, rb, kSecond * kb, l.measurement,
                                    l.information);
      } else {
        session.AddCandidate(0, ra, ka, rb, kb, l.measurement, l.information);
      }
    }
    if ((k + 1) % update_every == 0) session.Update(false);
  }
  const auto& first = graph.loops().front();
  session.AddCandidateByStamp(0, 0, kSecond * part, 0, 0, first.measurement,
                              first.information);
  session.Update(true);
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

  WriteSession(g, {""}, 10, dir / "session_reader" / "world2d.db");
  WriteSession(g3, {""}, 40, dir / "session_reader" / "world3d.db");
  WriteSession(g, {"a", "b"}, 10, dir / "session_reader" / "fleet2d.db");

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
