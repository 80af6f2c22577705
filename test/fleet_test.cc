// Four simulated robots and rrr_node serving them as a fleet
// (test/fleet.test): the test builds the same world from the robots'
// parameters to know which candidates are false.
#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <std_msgs/Bool.h>
#include <tf2_ros/transform_listener.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <variant>
#include <vector>

#include "ros_test_helpers.h"
#include "rrr/graph/chain_spans.h"
#include "rrr/io/g2o.h"
#include "rrr/session/session.h"
#include "rrr/sim/simulated_world.h"
#include "rrr_slam/GetAcceptedGraph.h"
#include "rrr_slam/GetDecisions.h"
#include "rrr_slam/SaveGraph.h"

namespace {

// A candidate's ends as the robots name them: "robot:id robot:id".
using Ends = std::string;

TEST(Fleet, EveryCandidateIsJudgedAsTheRecordedInputsReplayedAreJudged) {
  std::vector<std::string> robots;
  ASSERT_TRUE(ros::param::get("/rrr_node/robots", robots));
  rrr::WorldOptions world;
  int seed = 0;
  const std::string sim = "/" + robots.front() + "/simulated_robot/";
  ASSERT_TRUE(ros::param::get(sim + "poses", world.poses));
  ASSERT_TRUE(ros::param::get(sim + "false_loops", world.false_loops));
  ASSERT_TRUE(ros::param::get(sim + "group", world.group));
  ASSERT_TRUE(ros::param::get(sim + "seed", seed));
  world.seed = static_cast<std::uint64_t>(seed);
  const rrr::SimulatedWorld w = rrr::SimulateWorld(world);
  const int n = static_cast<int>(robots.size());
  // World pose p as robot:id (each robot drives a consecutive part).
  const auto name = [&](int p) {
    int r = n - 1;
    while (p < w.graph.num_poses() * r / n) --r;
    return robots[r] + ":" + std::to_string(p - w.graph.num_poses() * r / n);
  };
  std::set<Ends> false_ends;
  for (const int k : w.false_loops) {
    const auto& l = w.graph.loops()[k];
    false_ends.insert(name(l.from) + " " + name(l.to));
  }
  const uint64_t inputs = w.graph.num_poses() + w.graph.loops().size();

  ros::NodeHandle nh;
  rrr_test::DecisionTable stream(nh);
  std::map<std::string, bool> done;
  std::vector<ros::Subscriber> subs;
  for (const std::string& robot : robots) {
    subs.push_back(nh.subscribe<std_msgs::Bool>(
        "/" + robot + "/simulated_robot/done", 1,
        [&done, robot](const std_msgs::Bool::ConstPtr& m) {
          done[robot] = m->data;
        }));
  }
  tf2_ros::Buffer tf;
  tf2_ros::TransformListener listener(tf);
  ASSERT_TRUE(ros::service::waitForService("/rrr_node/get_status", 30000));
  ASSERT_TRUE(rrr_test::WaitFor(
      [&] {
        int finished = 0;
        for (const auto& [robot, d] : done) finished += d;
        return finished == n && rrr_test::Status().inputs_processed == inputs;
      },
      100.0))
      << "processed " << rrr_test::Status().inputs_processed << " of "
      << inputs;

  rrr_slam::Finish finish;
  ASSERT_TRUE(ros::service::call("/rrr_node/finish", finish));
  EXPECT_EQ(finish.response.pending, 0u);
  // The messages on ~decisions (each carries the candidates new, changed,
  // clustered or no longer waiting) add up to every candidate's state, as
  // ~get_decisions gives it whole.
  EXPECT_TRUE(rrr_test::WaitFor(
      [&] { return stream.AllDecided(w.graph.loops().size()); }, 10.0));
  EXPECT_EQ(stream.gaps(), 0);
  EXPECT_TRUE(rrr_test::SameDecisions(stream, rrr_test::Snapshot()));
  const std::string path =
      "/tmp/rrr_fleet_test_" + std::to_string(::getpid()) + ".g2o";
  rrr_slam::SaveGraph save;
  save.request.path = path;
  save.request.with_candidates = true;
  ASSERT_TRUE(ros::service::call("/rrr_node/save_graph", save));
  ASSERT_TRUE(save.response.success) << save.response.message;

  // The node's decisions, in the recorded graph's loop order.
  std::vector<std::pair<Ends, bool>> decisions;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("# DECISION ", 0) != 0) continue;
    std::istringstream fields(line.substr(11));
    std::string a, b, state;
    fields >> a >> b >> state;
    decisions.emplace_back(a + " " + b, state == "accepted");
  }
  const rrr::G2oFile file = rrr::ReadG2o(path);
  std::remove(path.c_str());
  const auto& graph = std::get<rrr::PoseGraph2>(file.graph);
  ASSERT_EQ(decisions.size(), graph.loops().size());
  EXPECT_EQ(decisions.size(), w.graph.loops().size());

  // ~get_decisions tells the same, naming robots and keyframes.
  rrr_slam::GetDecisions all;
  ASSERT_TRUE(ros::service::call("/rrr_node/get_decisions", all));
  EXPECT_TRUE(all.response.decisions.full);
  std::map<Ends, bool> told;
  for (const auto& d : all.response.decisions.decisions) {
    told[d.from_robot + ":" + std::to_string(d.from_id) + " " + d.to_robot +
         ":" + std::to_string(d.to_id)] =
        d.state == rrr_slam::LoopDecision::ACCEPTED;
    EXPECT_NE(d.state, rrr_slam::LoopDecision::PENDING);
  }
  for (const auto& [ends, accepted] : decisions) {
    ASSERT_EQ(told.count(ends), 1u) << ends;
    EXPECT_EQ(told[ends], accepted) << ends;
  }

  // The node's inputs replayed in the order it recorded them, through the
  // core alone, are judged as the node judged them: decisions depend only
  // on the inputs and their order.
  std::string database;
  ASSERT_TRUE(ros::param::get("/rrr_node/database", database));
  int window = 0;
  ASSERT_TRUE(ros::param::get("/rrr_node/cluster_window", window));
  rrr::SessionOptions options;
  options.rrr.cluster_window = window;
  options.restart_jump = 5.0;
  const std::string copy = database + ".copy";
  const auto replay = rrr::ReplaySession<rrr::Pose2>(database, copy, options);
  for (const std::string part : {"", "-wal", "-shm"}) {
    std::remove((copy + part).c_str());
  }
  ASSERT_EQ(replay->robots(), robots);
  ASSERT_EQ(replay->verifier().num_candidates(),
            static_cast<int>(all.response.decisions.decisions.size()));
  for (const auto& d : all.response.decisions.decisions) {
    EXPECT_EQ(
        replay->verifier().state(d.candidate) == rrr::LoopState::kAccepted,
        d.state == rrr_slam::LoopDecision::ACCEPTED)
        << "candidate " << d.candidate;
  }
  // A session per robot, and one more for the robot that restarted: no
  // odometry edge joins its two sessions. One map, no false loop in it,
  // most true loops.
  int restarts = 0;
  for (const std::string& robot : robots) {
    int restart_at = -1;
    ros::param::get("/" + robot + "/simulated_robot/restart_at", restart_at);
    restarts += restart_at > 0;
  }
  const std::vector<rrr::ChainSpan> chains = rrr::ChainSpansOf(graph);
  EXPECT_EQ(chains.size(), robots.size() + restarts);
  for (size_t c = 0; c < chains.size(); ++c) {
    EXPECT_EQ(replay->MapOfChain(static_cast<int>(c)), 0) << "chain " << c;
  }
  size_t true_accepted = 0;
  for (const auto& [ends, accepted] : decisions) {
    const bool is_false = false_ends.count(ends) > 0;
    if (accepted) {
      EXPECT_FALSE(is_false) << "false loop " << ends;
    }
    true_accepted += accepted && !is_false;
  }
  EXPECT_GE(true_accepted, 0.85 * (decisions.size() - false_ends.size()));
  // ~get_accepted_graph: every robot's keyframes (one map), named by robot
  // and keyframe id, with the accepted loops.
  rrr_slam::GetAcceptedGraph accepted_graph;
  ASSERT_TRUE(
      ros::service::call("/rrr_node/get_accepted_graph", accepted_graph));
  const rrr_slam::AcceptedGraph& ag = accepted_graph.response.graph;
  EXPECT_EQ(ag.header.frame_id, "map");
  ASSERT_EQ(static_cast<int>(ag.ids.size()), graph.num_poses());
  ASSERT_EQ(ag.robots.size(), ag.ids.size());
  ASSERT_EQ(ag.keyframe_ids.size(), ag.ids.size());
  EXPECT_EQ(ag.odometry.size(), graph.odometry().size());
  size_t accepted_loops = 0;
  for (const auto& [ends, accepted] : decisions) accepted_loops += accepted;
  EXPECT_EQ(ag.loops.size(), accepted_loops);
  std::set<std::string> named;
  for (size_t k = 0; k < ag.ids.size(); ++k) {
    named.insert(ag.robots[k] + ":" + std::to_string(ag.keyframe_ids[k]));
  }
  EXPECT_EQ(named.size(), ag.ids.size()) << "each keyframe named once";
  for (const auto& [ends, accepted] : decisions) {
    const std::string from = ends.substr(0, ends.find(' '));
    EXPECT_EQ(named.count(from), 1u) << from;
  }
  // Every robot on tf in the map frame.
  for (const std::string& robot : robots) {
    EXPECT_TRUE(tf.canTransform("map", robot + "/odom", ros::Time(0),
                                ros::Duration(2.0)))
        << robot;
  }
  const auto status = rrr_test::Status();
  EXPECT_EQ(status.invalid_messages, 0u);
  // The fleet's state, as one robot's node reports its own.
  EXPECT_EQ(status.sessions, chains.size());
  EXPECT_EQ(status.maps, 1u);
  EXPECT_GT(status.clusters, 0u);
  EXPECT_GT(status.noise_scale, 0.0);
  EXPECT_EQ(status.keyframes, static_cast<uint32_t>(graph.num_poses()));
  // Each candidate's latency, from its arrival to the update that published
  // it, is measured (none is published before it arrives).
  EXPECT_GT(status.candidate_latency_p50, 0.0);
  EXPECT_GE(status.candidate_latency_max, status.candidate_latency_p99);
  // /diagnostics: the node's status, OK (nothing invalid, nothing refused).
  diagnostic_msgs::DiagnosticArray::ConstPtr diagnostics;
  auto diagnostics_sub = nh.subscribe<diagnostic_msgs::DiagnosticArray>(
      "/diagnostics", 10, [&](const auto& m) { diagnostics = m; });
  ASSERT_TRUE(rrr_test::WaitFor([&] { return diagnostics != nullptr; }, 10.0));
  ASSERT_EQ(diagnostics->status.size(), 1u);
  EXPECT_EQ(diagnostics->status[0].level, diagnostic_msgs::DiagnosticStatus::OK)
      << diagnostics->status[0].message;
  // The update times, in the test's JUnit file.
  RecordProperty("update_p50_s", std::to_string(status.update_seconds_p50));
  RecordProperty("update_p99_s", std::to_string(status.update_seconds_p99));
  RecordProperty("update_max_s", std::to_string(status.max_update_seconds));
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "fleet_test");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
