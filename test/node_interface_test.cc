// rrr_node through its ROS interface: a generated world with known false
// loops goes in as odometry and loop-closure messages (by id, by stamp, ahead
// of its keyframe, and invalid ones); decisions, path, markers, tf and the
// services come out.
#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <nav_msgs/Path.h>
#include <ros/ros.h>
#include <tf2_ros/transform_listener.h>
#include <visualization_msgs/MarkerArray.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>

#include "../src/ros/msg_conversion.h"
#include "ros_test_helpers.h"
#include "rrr/graph/odometry_noise.h"
#include "rrr/io/g2o.h"
#include "rrr/rrr/map/verify_with_map.h"
#include "rrr/rrr/published/batch_verifier.h"
#include "rrr/sim/simulated_world.h"
#include "rrr/solver/pose_graph_solver.h"
#include "rrr_slam/AcceptedGraph.h"
#include "rrr_slam/Decisions.h"
#include "rrr_slam/Finish.h"
#include "rrr_slam/GetAcceptedGraph.h"
#include "rrr_slam/Keyframe.h"
#include "rrr_slam/LoopClosure.h"
#include "rrr_slam/SaveGraph.h"

namespace {

using Pairs = std::set<std::pair<int64_t, int64_t>>;

ros::Time StampOf(int pose) { return ros::Time(100.0 + 0.2 * pose); }

rrr_slam::LoopClosure LoopMsg(const rrr::PoseGraph<rrr::Pose2>& g,
                              const rrr::Constraint<rrr::Pose2>& e) {
  rrr_slam::LoopClosure m;
  m.header.stamp = StampOf(std::max(e.from, e.to));
  m.header.frame_id = "base_link";
  m.reference = rrr_slam::LoopClosure::BY_ID;
  m.from_id = g.ids()[e.from];
  m.to_id = g.ids()[e.to];
  m.relative_pose.pose = rrr_ros::ToRos(e.measurement);
  m.relative_pose.covariance =
      rrr_ros::CovarianceFromInformation<rrr::Pose2>(e.information);
  m.confidence = -1;
  return m;
}

TEST(RrrNode, JudgesAGeneratedWorldThroughItsInterface) {
  ros::NodeHandle nh;
  rrr::WorldOptions world_options;
  // A world where the two procedures decide differently (map 46 loops,
  // published 42, neither a false one), so that each run proves the node
  // follows its own procedure.
  world_options.poses = 400;
  world_options.false_loops = 12;
  world_options.group = 3;
  world_options.seed = 2;
  const rrr::SimulatedWorld world = rrr::SimulateWorld(world_options);
  const auto& g = world.graph;

  // What `rrr verify` decides on the same graph with the node's procedure
  // and threads (the node's other options are the defaults).
  rrr::RrrOptions options;
  std::string procedure;
  ASSERT_TRUE(ros::param::get("/rrr_node/procedure", procedure));
  ASSERT_TRUE(rrr::ParseProcedure(procedure, &options.procedure));
  ASSERT_TRUE(ros::param::get("/rrr_node/threads", options.threads));
  rrr::Verdict verdict;
  rrr::MapVerifierStats expected_stats;  // published: the information as given
  if (options.procedure == rrr::Procedure::kMap) {
    verdict =
        rrr::VerifyWithMap<rrr::Pose2>(g, options, nullptr, &expected_stats);
  } else {
    rrr::PoseGraphSolver<rrr::Pose2> solver(g, options.iterations);
    verdict = rrr::VerifyBatch(rrr::LoopEnds(g), solver, options);
  }
  Pairs expected;
  for (const int k : verdict.accepted) {
    expected.insert({g.ids()[g.loops()[k].from], g.ids()[g.loops()[k].to]});
  }
  Pairs false_pairs;
  for (const int k : world.false_loops) {
    false_pairs.insert({g.ids()[g.loops()[k].from], g.ids()[g.loops()[k].to]});
  }

  rrr_test::DecisionTable decisions(nh);
  nav_msgs::Path::ConstPtr path;
  visualization_msgs::MarkerArray::ConstPtr markers;
  auto path_sub = nh.subscribe<nav_msgs::Path>(
      "/rrr_node/path", 10, [&](const auto& m) { path = m; });
  auto marker_sub = nh.subscribe<visualization_msgs::MarkerArray>(
      "/rrr_node/graph", 10, [&](const auto& m) { markers = m; });
  int64_t newest_keyframe = -1;
  auto keyframe_sub = nh.subscribe<rrr_slam::Keyframe>(
      "/rrr_node/keyframes", 10000,
      [&](const auto& m) { newest_keyframe = m->id; });
  auto odom_pub = nh.advertise<nav_msgs::Odometry>("/odom", 10000);
  auto loop_pub = nh.advertise<rrr_slam::LoopClosure>("/loop_closures", 10000);
  // Its keyframes too: the candidates below wait for them, and one missed
  // before the connection stands would never come again.
  ASSERT_TRUE(rrr_test::WaitFor(
      [&] {
        return odom_pub.getNumSubscribers() > 0 &&
               loop_pub.getNumSubscribers() > 0 &&
               keyframe_sub.getNumPublishers() > 0;
      },
      30.0))
      << "rrr_node did not subscribe, or its keyframes are not connected";
  ASSERT_TRUE(ros::service::waitForService("/rrr_node/finish", 30000));

  std::vector<std::vector<int>> loops_at(g.num_poses());
  for (size_t k = 0; k < g.loops().size(); ++k) {
    const auto& e = g.loops()[k];
    loops_at[std::max(e.from, e.to)].push_back(static_cast<int>(k));
  }
  // Loop 0 is sent 5 poses before its later keyframe exists (it must wait);
  // loop 1 names its poses by time stamp.
  const int early = std::max(g.loops()[0].from, g.loops()[0].to) - 5;
  ASSERT_GT(early, 0);
  int loops_sent = 0, invalid_sent = 0;
  const std::vector<rrr::Pose2> chain = g.ComposeOdometry();
  rrr::OdometryCovariance covariance = rrr::OdometryCovariance::Zero();
  for (int p = 0; p < g.num_poses(); ++p) {
    nav_msgs::Odometry odom;
    odom.header.stamp = StampOf(p);
    odom.header.frame_id = "odom";
    odom.child_frame_id = "base_link";
    odom.pose.pose = rrr_ros::ToRos(chain[p]);
    // The pose covariance grows by each step's (REP 105): the node recovers
    // each edge's information from the growth, so its graph is `g`.
    if (p > 0) {
      covariance = rrr::OdometryNoiseModel<rrr::Pose2>::Grow(
          covariance, chain[p], g.odometry()[p - 1].information);
    }
    odom.pose.covariance = rrr_ros::ToRos(covariance);
    odom_pub.publish(odom);
    // Odometry and candidates come on two topics, so either may overtake
    // the other: a candidate is sent once the node has made the keyframe it
    // follows, so that the node takes the inputs in the order of `g` and
    // decides, with every reason, as rrr verify does on `g`. (Loop 0 is
    // sent early on purpose; it waits for its keyframe.) The load test
    // sends inputs as fast as they go.
    if (!loops_at[p].empty()) {
      ASSERT_TRUE(rrr_test::WaitFor([&] { return newest_keyframe >= p; }, 30.0))
          << "keyframe " << p << " not published";
    }
    if (p == early) {
      loop_pub.publish(LoopMsg(g, g.loops()[0]));
      ++loops_sent;
    }
    for (const int k : loops_at[p]) {
      if (k == 0) continue;
      rrr_slam::LoopClosure m = LoopMsg(g, g.loops()[k]);
      if (k == 1) {
        m.reference = rrr_slam::LoopClosure::BY_STAMP;
        m.from_stamp = StampOf(g.loops()[k].from) + ros::Duration(0.01);
        m.to_stamp = StampOf(g.loops()[k].to) - ros::Duration(0.01);
      }
      loop_pub.publish(m);
      ++loops_sent;
    }
    if (p == 200) {  // four invalid candidates and one naming no keyframe
      rrr_slam::LoopClosure bad = LoopMsg(g, g.loops()[2]);
      bad.relative_pose.pose.position.x =
          std::numeric_limits<double>::quiet_NaN();
      loop_pub.publish(bad);
      bad = LoopMsg(g, g.loops()[2]);
      bad.relative_pose.covariance[0] = -1.0;
      loop_pub.publish(bad);
      bad = LoopMsg(g, g.loops()[2]);
      bad.header.frame_id = "camera";
      loop_pub.publish(bad);
      bad = LoopMsg(g, g.loops()[2]);
      bad.reference = 7;
      loop_pub.publish(bad);
      bad = LoopMsg(g, g.loops()[2]);
      bad.from_id = -4;
      loop_pub.publish(bad);
      invalid_sent += 4;
      loops_sent += 5;
    }
    // ... and the next odometry once the node has them.
    if (!loops_at[p].empty()) {
      ASSERT_TRUE(rrr_test::WaitFor(
          [&] {
            return rrr_test::Status().loop_closures_received >=
                   static_cast<uint64_t>(loops_sent);
          },
          30.0));
    }
    if (p % 50 == 0) ros::WallDuration(0.01).sleep();
  }
  ASSERT_TRUE(rrr_test::WaitFor(
      [&] {
        const auto s = rrr_test::Status();
        return s.odometry_received == static_cast<uint64_t>(g.num_poses()) &&
               s.loop_closures_received == static_cast<uint64_t>(loops_sent) &&
               s.queue_length == 0;
      },
      60.0))
      << "not every input reached the node";

  rrr_slam::Finish finish;
  ASSERT_TRUE(ros::service::call("/rrr_node/finish", finish));
  EXPECT_EQ(finish.response.pending, 0u);
  EXPECT_EQ(finish.response.waiting, 0u);
  // The messages published by finish: nothing pending, every keyframe, every
  // candidate drawn as decided (older messages may still be arriving).
  const auto decided_points = [&] {
    size_t n = 0;
    for (const auto& m : markers->markers) {
      if (m.ns == "pending" && !m.points.empty()) return size_t{0};
      if (m.ns == "accepted" || m.ns == "rejected") n += m.points.size();
    }
    return n;
  };
  ASSERT_TRUE(rrr_test::WaitFor(
      [&] {
        return decisions.AllDecided(g.loops().size()) && path &&
               path->poses.size() == static_cast<size_t>(g.num_poses()) &&
               markers && decided_points() == 2 * g.loops().size();
      },
      30.0));

  // Decisions: the batch answer, every false loop rejected. The messages
  // on ~decisions (each carries what changed or is new) add up to every
  // candidate's state, as ~get_decisions gives it whole.
  EXPECT_EQ(decisions.gaps(), 0);
  EXPECT_TRUE(rrr_test::SameDecisions(decisions, rrr_test::Snapshot()));
  Pairs accepted;
  for (const auto& d : decisions.decisions()) {
    EXPECT_FALSE(d.waiting);
    EXPECT_NE(d.state, rrr_slam::LoopDecision::PENDING);
    if (d.state == rrr_slam::LoopDecision::ACCEPTED)
      accepted.insert({d.from_id, d.to_id});
    if (options.procedure == rrr::Procedure::kMap) {
      EXPECT_NE(d.test, "not_judged");
      EXPECT_GE(d.decided_at, 0);
      if (d.test != "outweighed") {
        EXPECT_EQ(d.statistic < d.gate,
                  d.state == rrr_slam::LoopDecision::ACCEPTED);
      }
    }
  }
  // With the map procedure each carries the test that decided it, its
  // statistic and gate, as rrr verify reports them on `g`. The node's
  // odometry information is `g`'s to rounding (recovered from the
  // covariances), and rounding can make the arbiter record the reason of
  // a cluster whose refused link it takes back at the end at another pose
  // (never another decision or test): its figures are compared where the
  // pose is the same.
  if (options.procedure == rrr::Procedure::kMap) {
    std::map<std::pair<int64_t, int64_t>, rrr::DecisionReason> reason_of;
    for (size_t k = 0; k < g.loops().size(); ++k) {
      const auto& l = g.loops()[k];
      reason_of[{g.ids()[l.from], g.ids()[l.to]}] = verdict.reasons[k];
    }
    int same_pose = 0;
    for (const auto& d : decisions.decisions()) {
      ASSERT_EQ(reason_of.count({d.from_id, d.to_id}), 1u);
      const rrr::DecisionReason& r = reason_of[{d.from_id, d.to_id}];
      EXPECT_EQ(d.test, rrr::ToString(r.test));
      if (d.decided_at != g.ids()[r.pose]) continue;
      ++same_pose;
      EXPECT_NEAR(d.statistic, r.statistic, 1e-6 * std::abs(r.statistic));
      EXPECT_NEAR(d.gate, r.gate, 1e-6 * r.gate);
    }
    EXPECT_GE(same_pose, 0.75 * static_cast<double>(g.loops().size()));
  }
  EXPECT_EQ(decisions.decisions().size(), g.loops().size());
  EXPECT_EQ(accepted, expected);
  for (const auto& f : false_pairs) EXPECT_EQ(accepted.count(f), 0u);
  EXPECT_GT(accepted.size(), 0u);

  // The corrected path has every keyframe, in the map frame.
  EXPECT_EQ(path->header.frame_id, "map");
  EXPECT_EQ(path->poses.size(), static_cast<size_t>(g.num_poses()));

  // Markers: accepted loops green, rejected red, two points each.
  std::map<std::string, size_t> points;
  for (const auto& m : markers->markers) points[m.ns] = m.points.size();
  EXPECT_EQ(points["accepted"], 2 * accepted.size());
  EXPECT_EQ(points["rejected"], 2 * (g.loops().size() - accepted.size()));
  EXPECT_EQ(points["pending"], 0u);
  for (const auto& m : markers->markers) {
    // Empty lists clear old markers; the others are drawn.
    EXPECT_EQ(m.action, m.points.empty() ? visualization_msgs::Marker::DELETE
                                         : visualization_msgs::Marker::ADD)
        << m.ns;
  }

  // map -> odom on tf.
  tf2_ros::Buffer buffer;
  tf2_ros::TransformListener listener(buffer);
  EXPECT_TRUE(
      buffer.canTransform("map", "odom", ros::Time(0), ros::Duration(10.0)));

  // Status: the invalid messages counted, nothing lost.
  const auto status = rrr_test::Status();
  EXPECT_EQ(status.invalid_messages, static_cast<uint64_t>(invalid_sent));
  EXPECT_EQ(status.skipped_unknown_poses, 1u);
  EXPECT_EQ(status.inputs_dropped, 0u);
  EXPECT_EQ(status.keyframes, static_cast<uint32_t>(g.num_poses()));
  EXPECT_EQ(status.candidates, g.loops().size());
  // The scales of the gates at the end: rrr verify's on `g`, to rounding.
  EXPECT_NEAR(status.noise_scale, expected_stats.noise_scale,
              1e-6 * expected_stats.noise_scale);
  EXPECT_NEAR(status.group_noise_scale, expected_stats.group_noise_scale,
              1e-6 * expected_stats.group_noise_scale);
  EXPECT_GE(status.group_noise_scale, status.noise_scale);

  // /diagnostics warns that invalid messages were ignored.
  diagnostic_msgs::DiagnosticArray::ConstPtr diagnostics;
  auto diagnostics_sub = nh.subscribe<diagnostic_msgs::DiagnosticArray>(
      "/diagnostics", 10, [&](const auto& m) { diagnostics = m; });
  ASSERT_TRUE(rrr_test::WaitFor([&] { return diagnostics != nullptr; }, 10.0));
  ASSERT_EQ(diagnostics->status.size(), 1u);
  EXPECT_EQ(diagnostics->status[0].level,
            diagnostic_msgs::DiagnosticStatus::WARN);
  EXPECT_EQ(diagnostics->status[0].message, "invalid messages ignored");

  // Save: odometry plus the accepted loops, readable as g2o.
  rrr_slam::SaveGraph save;
  save.request.path = ::testing::TempDir() + "rrr_node_saved.g2o";
  ASSERT_TRUE(ros::service::call("/rrr_node/save_graph", save));
  EXPECT_TRUE(save.response.success) << save.response.message;
  const auto saved =
      std::get<rrr::PoseGraph2>(rrr::ReadG2o(save.request.path).graph);
  EXPECT_EQ(saved.num_poses(), g.num_poses());
  EXPECT_EQ(saved.loops().size(), accepted.size());

  // ~get_accepted_graph: every keyframe, its odometry, the accepted loops.
  const auto expect_final_graph = [&](const rrr_slam::AcceptedGraph& graph) {
    EXPECT_EQ(graph.poses.size(), static_cast<size_t>(g.num_poses()));
    EXPECT_EQ(graph.odometry.size(), g.odometry().size());
    Pairs graph_loops;
    for (const auto& e : graph.loops) graph_loops.insert({e.from_id, e.to_id});
    EXPECT_EQ(graph_loops, accepted);
  };
  rrr_slam::GetAcceptedGraph graph;
  ASSERT_TRUE(ros::service::call("/rrr_node/get_accepted_graph", graph));
  expect_final_graph(graph.response.graph);

  // Nobody subscribed to ~accepted_graph during the run, so it was never
  // built; a subscriber that joins after ~finish gets the final graph.
  rrr_slam::AcceptedGraph::ConstPtr late;
  auto late_sub = nh.subscribe<rrr_slam::AcceptedGraph>(
      "/rrr_node/accepted_graph", 1, [&](const auto& m) { late = m; });
  ASSERT_TRUE(rrr_test::WaitFor([&] { return late != nullptr; }, 10.0))
      << "a subscriber that joined after ~finish got no accepted graph";
  expect_final_graph(*late);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "node_interface_test");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
