// The end of a bag replay through rrr_node equals `rrr verify` on the graph
// the bag was made from. Arguments: rrr verify's report, the graph, and the
// style of the bag's odometry covariances ("growing": the node recovers the
// graph's information, so the report holds the expected decisions;
// "constant": the node uses its motion rule, which the test applies to the
// graph before verifying it with the map procedure).
#include <gtest/gtest.h>
#include <ros/ros.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <set>

#include "ros_test_helpers.h"
#include "rrr/graph/odometry_chain.h"
#include "rrr/graph/odometry_noise.h"
#include "rrr/io/g2o.h"
#include "rrr/rrr/map/verify_with_map.h"
#include "rrr_slam/Decisions.h"

namespace {

std::string g_report, g_graph, g_style;
using Pairs = std::set<std::pair<int64_t, int64_t>>;

// The map procedure's decisions on the graph with every odometry edge's
// information replaced by the node's motion rule (its parameters read from
// the node's namespace).
Pairs DecisionsWithTheMotionRule() {
  auto graph = std::get<rrr::PoseGraph2>(rrr::ReadG2o(g_graph).graph);
  std::vector<double> per_unit;
  double min_motion = 0.0;
  int window = 0;
  EXPECT_TRUE(ros::param::get("/rrr_node/odometry/information", per_unit));
  EXPECT_TRUE(ros::param::get("/rrr_node/odometry/min_motion", min_motion));
  EXPECT_TRUE(ros::param::get("/rrr_node/cluster_window", window));
  rrr::Pose2::Jacobian information = rrr::Pose2::Jacobian::Zero();
  for (int k = 0; k < 3; ++k) information(k, k) = per_unit.at(k);
  const rrr::OdometryNoiseModel<rrr::Pose2> model(information, min_motion);
  rrr::PoseGraph2 reweighed;
  for (int k = 0; k < graph.num_poses(); ++k) {
    reweighed.AddPose(graph.ids()[k], graph.estimates()[k]);
  }
  const rrr::OdometryChain<rrr::Pose2> chain = rrr::ChainOf(graph);
  for (int k = 1; k < graph.num_poses(); ++k) {
    rrr::Constraint<rrr::Pose2> step = chain.Between(k - 1, k);
    step.information = model.FromMotion(step.measurement);
    reweighed.AddEdge(step);
  }
  for (const auto& loop : graph.loops()) reweighed.AddEdge(loop);
  rrr::RrrOptions options;
  options.cluster_window = window;
  const rrr::Verdict verdict = rrr::VerifyWithMap(reweighed, options);
  Pairs out;
  for (const int k : verdict.accepted) {
    const auto& l = reweighed.loops()[k];
    out.insert({reweighed.ids()[l.from], reweighed.ids()[l.to]});
  }
  return out;
}

TEST(RrrNode, ReplayEndsWithTheBatchDecisions) {
  std::ifstream in(g_report);
  ASSERT_TRUE(in) << "cannot read " << g_report;
  const nlohmann::json report = nlohmann::json::parse(in);
  const auto poses = report["poses"].get<uint64_t>();
  const auto candidates = report["candidates"].get<uint64_t>();
  Pairs expected;
  if (g_style == "constant") {
    expected = DecisionsWithTheMotionRule();
  } else {
    for (const auto& p : report["accepted"]) {
      expected.insert({p[0].get<int64_t>(), p[1].get<int64_t>()});
    }
  }

  ros::NodeHandle nh;
  ASSERT_TRUE(ros::service::waitForService("/rrr_node/get_status", 30000));
  ASSERT_TRUE(rrr_test::WaitFor(
      [&] {
        const auto s = rrr_test::Status();
        return s.inputs_processed == poses + candidates;
      },
      150.0))
      << "the replay did not reach the node in full";
  // Every candidate, none pending, once every cluster is judged.
  const rrr_slam::Decisions decisions = rrr_test::FinishAndSnapshot();
  ASSERT_TRUE(decisions.full) << "~finish or ~get_decisions failed";
  ASSERT_EQ(decisions.pending, 0u);
  std::set<std::pair<int64_t, int64_t>> accepted;
  for (const auto& d : decisions.decisions) {
    if (d.state == rrr_slam::LoopDecision::ACCEPTED)
      accepted.insert({d.from_id, d.to_id});
  }
  EXPECT_EQ(accepted, expected);
  EXPECT_EQ(decisions.decisions.size(), candidates);
  const auto status = rrr_test::Status();
  EXPECT_EQ(status.inputs_dropped, 0u);
  EXPECT_EQ(status.invalid_messages, 0u);
  // Every odometry edge took the rule its style calls for.
  const uint64_t edges = poses - 1;
  if (g_style == "constant") {
    EXPECT_EQ(status.odometry_information_from_motion, edges);
  } else {
    EXPECT_EQ(status.odometry_information_from_covariance, edges);
  }
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "replay_test");
  if (argc > 3) {
    g_report = argv[1];
    g_graph = argv[2];
    g_style = argv[3];
  }
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
