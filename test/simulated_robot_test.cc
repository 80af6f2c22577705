// The simulated robot and rrr_node together (test/simulated_robot.test): the
// test builds the same world from the robot's parameters to know which
// candidates are false.
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <std_msgs/Bool.h>

#include <set>

#include "ros_test_helpers.h"
#include "rrr/rrr/map/verify_with_map.h"
#include "rrr/sim/simulated_world.h"
#include "rrr_slam/Decisions.h"

namespace {

using Pairs = std::set<std::pair<int64_t, int64_t>>;

TEST(SimulatedRobot, EveryCandidateIsJudgedAsInABatchRun) {
  rrr::WorldOptions world;
  int seed = 0;
  ASSERT_TRUE(ros::param::get("/simulated_robot/poses", world.poses));
  ASSERT_TRUE(
      ros::param::get("/simulated_robot/false_loops", world.false_loops));
  ASSERT_TRUE(ros::param::get("/simulated_robot/group", world.group));
  ASSERT_TRUE(ros::param::get("/simulated_robot/seed", seed));
  world.seed = static_cast<std::uint64_t>(seed);
  const rrr::SimulatedWorld w = rrr::SimulateWorld(world);
  Pairs false_pairs;
  for (const int k : w.false_loops) {
    const auto& l = w.graph.loops()[k];
    false_pairs.insert({w.graph.ids()[l.from], w.graph.ids()[l.to]});
  }
  const size_t candidates = w.graph.loops().size();
  const uint64_t inputs = w.graph.num_poses() + candidates;

  ros::NodeHandle nh;
  bool done = false;
  auto done_sub = nh.subscribe<std_msgs::Bool>(
      "/simulated_robot/done", 1, [&](const auto& m) { done = m->data; });
  ASSERT_TRUE(ros::service::waitForService("/rrr_node/get_status", 30000));
  ASSERT_TRUE(rrr_test::WaitFor(
      [&] { return done && rrr_test::Status().inputs_processed == inputs; },
      100.0))
      << "processed " << rrr_test::Status().inputs_processed << " of "
      << inputs;
  // Every candidate, none pending, once every cluster is judged.
  const rrr_slam::Decisions decisions = rrr_test::FinishAndSnapshot();
  ASSERT_TRUE(decisions.full) << "~finish or ~get_decisions failed";
  ASSERT_EQ(decisions.pending, 0u);
  // The node, fed live, decides as the map procedure does on the whole
  // world at once (its odometry information recovered from the growing
  // covariances the robot publishes).
  Pairs accepted, expected;
  for (const auto& d : decisions.decisions) {
    if (d.state == rrr_slam::LoopDecision::ACCEPTED) {
      accepted.insert({d.from_id, d.to_id});
    }
  }
  int window = 0;
  ASSERT_TRUE(ros::param::get("/rrr_node/cluster_window", window));
  rrr::RrrOptions options;
  options.cluster_window = window;
  for (const int k : rrr::VerifyWithMap(w.graph, options).accepted) {
    const auto& l = w.graph.loops()[k];
    expected.insert({w.graph.ids()[l.from], w.graph.ids()[l.to]});
  }
  EXPECT_EQ(accepted, expected);
  size_t true_accepted = 0;
  for (const auto& pair : accepted)
    true_accepted += false_pairs.count(pair) == 0;
  EXPECT_GE(true_accepted, 0.85 * (candidates - false_pairs.size()));
  const auto status = rrr_test::Status();
  EXPECT_EQ(status.invalid_messages, 0u);
  EXPECT_EQ(status.skipped_unknown_poses, 0u);  // every stamp resolved
  EXPECT_EQ(status.odometry_information_from_covariance,
            static_cast<uint64_t>(w.graph.num_poses() - 1));
  // Driving back past where it started is no restart of its odometry.
  EXPECT_EQ(status.odometry_restarts_joined, 0u);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "simulated_robot_test");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
