// The end of a bag replay through rrr_node equals `rrr verify` on the graph
// the bag was made from (its report is the first argument).
#include <gtest/gtest.h>
#include <ros/ros.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <set>

#include "ros_test_helpers.h"
#include "rrr_slam/Decisions.h"
#include "rrr_slam/Finish.h"

namespace {

std::string g_report;

TEST(RrrNode, ReplayEndsWithTheBatchDecisions) {
  std::ifstream in(g_report);
  ASSERT_TRUE(in) << "cannot read " << g_report;
  const nlohmann::json report = nlohmann::json::parse(in);
  const auto poses = report["poses"].get<uint64_t>();
  const auto candidates = report["candidates"].get<uint64_t>();
  std::set<std::pair<int64_t, int64_t>> expected;
  for (const auto& p : report["accepted"]) {
    expected.insert({p[0].get<int64_t>(), p[1].get<int64_t>()});
  }

  ros::NodeHandle nh;
  rrr_slam::Decisions::ConstPtr decisions;
  auto sub = nh.subscribe<rrr_slam::Decisions>(
      "/rrr_node/decisions", 10, [&](const auto& m) { decisions = m; });
  ASSERT_TRUE(ros::service::waitForService("/rrr_node/get_status", 30000));
  ASSERT_TRUE(rrr_test::WaitFor(
      [&] {
        const auto s = rrr_test::Status();
        return s.odometry_received == poses &&
               s.loop_closures_received == candidates && s.queue_length == 0;
      },
      150.0))
      << "the replay did not reach the node in full";
  rrr_slam::Finish finish;
  ASSERT_TRUE(ros::service::call("/rrr_node/finish", finish));
  // The message published by finish: every candidate, none pending.
  ASSERT_TRUE(rrr_test::WaitFor(
      [&] {
        return decisions && decisions->pending == 0 &&
               decisions->decisions.size() == candidates;
      },
      30.0));
  std::set<std::pair<int64_t, int64_t>> accepted;
  for (const auto& d : decisions->decisions) {
    if (d.state == rrr_slam::LoopDecision::ACCEPTED)
      accepted.insert({d.from_id, d.to_id});
  }
  EXPECT_EQ(accepted, expected);
  EXPECT_EQ(decisions->decisions.size(), candidates);
  const auto status = rrr_test::Status();
  EXPECT_EQ(status.inputs_dropped, 0u);
  EXPECT_EQ(status.invalid_messages, 0u);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "replay_test");
  if (argc > 1) g_report = argv[1];
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
