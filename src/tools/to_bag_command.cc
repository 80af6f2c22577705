// rrr to-bag: a g2o file as a bag of rrr_node's input topics.
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>

#include <fstream>
#include <iostream>

#include "../ros/msg_conversion.h"
#include "commands.h"
#include "graph_file.h"
#include "output_paths.h"
#include "rrr/eval/ground_truth.h"
#include "rrr/graph/odometry_chain.h"
#include "rrr/graph/odometry_noise.h"
#include "rrr/io/input_error.h"
#include "rrr_slam/LoopClosure.h"

namespace rrr {
namespace {

struct ToBagArgs {
  std::string input, output, timestamps;
  double rate = 5.0;
  std::string odom_topic = "odom", loop_topic = "loop_closures";
  std::string odom_frame = "odom", base_frame = "base_link";
  std::string covariance = "growing";
};

// The pose covariance of a constant-covariance driver (diff_drive_controller's
// pose_covariance_diagonal in its documented configuration).
OdometryCovariance ConstantDriverCovariance() {
  OdometryCovariance c = OdometryCovariance::Zero();
  c.diagonal() << 0.001, 0.001, 1e6, 1e6, 1e6, 1e3;
  return c;
}

template <class Pose>
void ToBag(const PoseGraph<Pose>& graph, const ToBagArgs& args) {
  const int n = graph.num_poses();
  for (int k = 0; k < n; ++k) {
    if (graph.ids()[k] != k) {
      throw InputError(
          args.input, 0,
          "pose ids must be 0, 1, 2, ... (the node's keyframe ids); "
          "pose " +
              std::to_string(k) + " has id " + std::to_string(graph.ids()[k]));
    }
  }
  std::vector<double> times;
  if (!args.timestamps.empty()) {
    times = ReadTimestamps(args.timestamps);
    if (static_cast<int>(times.size()) < n) {
      throw InputError(args.timestamps, 0,
                       "has " + std::to_string(times.size()) +
                           " time stamps for " + std::to_string(n) + " poses");
    }
    for (int k = 1; k < n; ++k) {
      if (!(times[k] >= times[k - 1])) {
        throw InputError(args.timestamps, k + 1,
                         "time stamps must not decrease");
      }
    }
  } else {
    for (int k = 0; k < n; ++k) times.push_back(1.0 + k / args.rate);
  }
  // Each loop is published just after its later pose.
  std::vector<std::vector<int>> loops_at(n);
  for (size_t l = 0; l < graph.loops().size(); ++l) {
    const auto& e = graph.loops()[l];
    loops_at[std::max(e.from, e.to)].push_back(static_cast<int>(l));
  }
  const OdometryChain<Pose> steps = ChainOf(graph);
  const std::vector<Pose> chain = graph.ComposeOdometry();
  const bool growing = args.covariance == "growing";
  OdometryCovariance covariance =
      growing ? OdometryCovariance::Zero() : ConstantDriverCovariance();

  rosbag::Bag bag;
  try {
    bag.open(args.output, rosbag::bagmode::Write);
  } catch (const rosbag::BagException& e) {
    throw InputError(args.output, 0, e.what());
  }
  uint32_t seq = 0;
  for (int k = 0; k < n; ++k) {
    const ros::Time stamp(times[k]);
    nav_msgs::Odometry odom;
    odom.header.seq = k;
    odom.header.stamp = stamp;
    odom.header.frame_id = args.odom_frame;
    odom.child_frame_id = args.base_frame;
    odom.pose.pose = rrr_ros::ToRos(chain[k]);
    // The pose covariance in the odometry frame: growing by each step's
    // covariance (what the node recovers exactly), or a driver's constant.
    if (growing && k > 0) {
      covariance = OdometryNoiseModel<Pose>::Grow(
          covariance, chain[k], steps.Between(k - 1, k).information);
    }
    odom.pose.covariance = rrr_ros::ToRos(covariance);
    bag.write(args.odom_topic, stamp, odom);
    for (const int l : loops_at[k]) {
      const auto& e = graph.loops()[l];
      rrr_slam::LoopClosure loop;
      loop.header.seq = seq++;
      loop.header.stamp = stamp + ros::Duration(1e-6);
      loop.header.frame_id = args.base_frame;
      loop.reference = rrr_slam::LoopClosure::BY_ID;
      loop.from_id = graph.ids()[e.from];
      loop.to_id = graph.ids()[e.to];
      loop.from_stamp = ros::Time(times[e.from]);
      loop.to_stamp = ros::Time(times[e.to]);
      loop.relative_pose.pose = rrr_ros::ToRos(e.measurement);
      loop.relative_pose.covariance =
          rrr_ros::CovarianceFromInformation<Pose>(e.information);
      loop.confidence = -1.0;
      bag.write(args.loop_topic, loop.header.stamp, loop);
    }
  }
  bag.close();
  std::cout << "wrote " << n << " odometry messages and "
            << graph.loops().size() << " loop candidates ("
            << times[n - 1] - times[0] << " s) to " << args.output << "\n";
}

}  // namespace

void AddToBagCommand(CLI::App& app) {
  auto args = std::make_shared<ToBagArgs>();
  CLI::App* cmd = app.add_subcommand("to-bag", kToBagDescription);
  cmd->add_option("input", args->input, "g2o file with pose ids 0, 1, 2, ...")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--timestamps", args->timestamps, "time of pose k on line k")
      ->check(CLI::ExistingFile);
  cmd->add_option("--rate", args->rate,
                  "odometry rate without --timestamps (Hz)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--odom-topic", args->odom_topic)->capture_default_str();
  cmd->add_option("--loop-topic", args->loop_topic)->capture_default_str();
  cmd->add_option("--odom-frame", args->odom_frame)->capture_default_str();
  cmd->add_option("--base-frame", args->base_frame)->capture_default_str();
  cmd->add_option("--covariance", args->covariance,
                  "odometry pose covariance: growing (the pose's, in the "
                  "odometry frame, as robot_localization; the node recovers "
                  "each edge's information from it) or constant (as "
                  "diff_drive_controller; the node falls back to "
                  "odometry/information)")
      ->capture_default_str()
      ->check(CLI::IsMember({"growing", "constant"}));
  cmd->add_option("-o,--output", args->output, "bag to write")->required();
  cmd->callback([args] {
    CheckOutputPaths({args->input, args->timestamps}, {args->output});
    const AnyPoseGraph graph = LoadGraph(args->input).graph;
    std::visit([&](const auto& g) { ToBag(g, *args); }, graph);
  });
}

}  // namespace rrr
