// rrr to-bag: a g2o file as a bag of rrr_node's input topics.
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>

#include <algorithm>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <optional>
#include <set>

#include "../ros/msg_conversion.h"
#include "commands.h"
#include "graph_file.h"
#include "output_paths.h"
#include "rrr/eval/ground_truth.h"
#include "rrr/graph/chain_spans.h"
#include "rrr/graph/odometry_chain.h"
#include "rrr/graph/odometry_noise.h"
#include "rrr/io/input_error.h"
#include "rrr/io/symbol_key.h"
#include "rrr_slam/FleetLoopClosure.h"
#include "rrr_slam/LoopClosure.h"

namespace rrr {
namespace {

struct ToBagArgs {
  std::string input, output, timestamps;
  double rate = 5.0;
  std::string odom_topic = "odom", loop_topic = "loop_closures";
  std::string fleet_loop_topic = "fleet_loop_closures";
  std::string odom_frame = "odom", base_frame = "base_link";
  std::string covariance = "growing";
  std::string robot;  // "": one robot, its topics without a prefix
  double restart_jump = 1.0;
};

// The pose covariance of a constant-covariance driver (diff_drive_controller's
// pose_covariance_diagonal in its documented configuration).
OdometryCovariance ConstantDriverCovariance() {
  OdometryCovariance c = OdometryCovariance::Zero();
  c.diagonal() << 0.001, 0.001, 1e6, 1e6, 1e6, 1e3;
  return c;
}

// A pose of the graph as the bag names it: its robot ("" for the one robot
// of a graph of one chain) and its keyframe id there.
struct BagPose {
  std::string robot;
  std::int64_t keyframe = 0;
};

// `name` in robot `robot`'s namespace ("" : as it is).
std::string OfRobot(const std::string& robot, const std::string& name) {
  return robot.empty() ? name : robot + "/" + name;
}

// Names every pose of `graph` (chains `spans`). One chain: one robot, its
// ids 0, 1, 2, ... are its keyframe ids. Several: each chain a session of
// the robot of its first pose's GTSAM symbol (else of `args.robot`, "" for
// the node's one robot), whose keyframes count on over its sessions, as
// rrr_node numbers them.
template <class Pose>
std::vector<BagPose> NameThePoses(const PoseGraph<Pose>& graph,
                                  const std::vector<ChainSpan>& spans,
                                  const ToBagArgs& args) {
  std::vector<BagPose> named(graph.num_poses());
  if (spans.size() == 1) {
    for (int k = 0; k < graph.num_poses(); ++k) {
      if (graph.ids()[k] != k) {
        throw InputError(args.input, 0,
                         "pose ids must be 0, 1, 2, ... (the node's keyframe "
                         "ids) in a graph of one odometry chain; pose " +
                             std::to_string(k) + " has id " +
                             std::to_string(graph.ids()[k]));
      }
      named[k] = {"", k};
    }
    return named;
  }
  std::map<std::string, std::int64_t> next_keyframe;
  for (const ChainSpan& span : spans) {
    const std::optional<SymbolKey> symbol = AsSymbol(graph.ids()[span.first]);
    const std::string robot =
        symbol ? std::string(1, symbol->robot) : args.robot;
    for (int k = span.first; k <= span.last; ++k) {
      named[k] = {robot, next_keyframe[robot]++};
    }
  }
  return named;
}

// The time of each pose: from `args.timestamps` (line k: pose k), else each
// robot's keyframe k at 1 + k / rate (robots drive side by side). Throws
// InputError if a time is not after 0, a robot's times decrease or there
// are too few.
std::vector<double> PoseTimes(const std::vector<BagPose>& named,
                              const ToBagArgs& args) {
  const int n = static_cast<int>(named.size());
  std::vector<double> times;
  if (args.timestamps.empty()) {
    for (const BagPose& pose : named) {
      times.push_back(1.0 + static_cast<double>(pose.keyframe) / args.rate);
    }
    return times;
  }
  times = ReadTimestamps(args.timestamps);
  if (static_cast<int>(times.size()) < n) {
    throw InputError(args.timestamps, 0,
                     "has " + std::to_string(times.size()) +
                         " time stamps for " + std::to_string(n) + " poses");
  }
  std::map<std::string, double> last;
  for (int k = 0; k < n; ++k) {
    if (!(times[k] > 0.0)) {
      throw InputError(args.timestamps, k + 1,
                       "time stamps must be after 0 (a bag holds nothing at "
                       "or before time 0)");
    }
    const auto previous = last.find(named[k].robot);
    if (previous != last.end() && !(times[k] >= previous->second)) {
      throw InputError(args.timestamps, k + 1,
                       "time stamps must not decrease along a robot's poses");
    }
    last[named[k].robot] = times[k];
  }
  return times;
}

// One message of the bag, written in the order of (time, order added).
struct BagMessage {
  double time;
  std::function<void(rosbag::Bag&, const ros::Time&)> write;
};

template <class Pose>
void ToBag(const PoseGraph<Pose>& graph, const ToBagArgs& args) {
  const std::vector<ChainSpan> spans = ChainSpansOf(graph);
  const std::vector<BagPose> named = NameThePoses(graph, spans, args);
  const std::vector<double> times = PoseTimes(named, args);
  const std::vector<OdometryChain<Pose>> chains = OdometryOf(graph, spans);
  const bool growing = args.covariance == "growing";
  std::vector<BagMessage> messages;
  std::map<std::string, Pose> session_end;  // by robot: its odometry there
  for (size_t c = 0; c < spans.size(); ++c) {
    const ChainSpan& span = spans[c];
    const OdometryChain<Pose>& steps = chains[c];
    const std::string& robot = named[span.first].robot;
    // Each session's odometry starts again at zero, as a restarted driver's:
    // the node must see the jump from where the last one ended.
    const auto previous = session_end.find(robot);
    if (previous != session_end.end() &&
        previous->second.translation().norm() <= args.restart_jump) {
      throw InputError(
          args.input, 0,
          "robot " + robot + "'s session from pose " +
              std::to_string(graph.ids()[span.first]) +
              " starts again at zero within --restart-jump (" +
              std::to_string(args.restart_jump) +
              " m) of where its previous one ended; the node would take it "
              "for the same session");
    }
    OdometryCovariance covariance =
        growing ? OdometryCovariance::Zero() : ConstantDriverCovariance();
    for (int k = 0; k < span.size(); ++k) {
      const int pose = span.first + k;
      const Pose odometry = steps.Relative(0, k);
      // The pose covariance in the odometry frame: growing by each step's
      // covariance (what the node recovers exactly), or a driver's constant.
      if (growing && k > 0) {
        covariance = OdometryNoiseModel<Pose>::Grow(
            covariance, odometry, steps.Between(k - 1, k).information);
      }
      nav_msgs::Odometry odom;
      odom.header.seq = static_cast<uint32_t>(named[pose].keyframe);
      odom.header.frame_id = OfRobot(robot, args.odom_frame);
      odom.child_frame_id = OfRobot(robot, args.base_frame);
      odom.pose.pose = rrr_ros::ToRos(odometry);
      odom.pose.covariance = rrr_ros::ToRos(covariance);
      const std::string topic = OfRobot(robot, args.odom_topic);
      messages.push_back(
          {times[pose], [odom, topic](rosbag::Bag& bag, const ros::Time& t) {
             nav_msgs::Odometry stamped = odom;
             stamped.header.stamp = t;
             bag.write(topic, t, stamped);
           }});
    }
    session_end[robot] = steps.Relative(0, span.size() - 1);
  }
  // Each loop just after the later of its poses, numbered in the order the
  // bag holds them: `header_of` is where a message of its kind has its header.
  uint32_t seq = 0;
  const auto queue_loop = [&messages, &seq](double time,
                                            const std::string& topic,
                                            auto message, auto header_of) {
    messages.push_back(
        {time, [message, header_of, &seq, &topic](rosbag::Bag& bag,
                                                  const ros::Time& t) mutable {
           header_of(message).seq = seq++;
           header_of(message).stamp = t;
           bag.write(topic, t, message);
         }});
  };
  for (const auto& e : graph.loops()) {
    rrr_slam::LoopClosure loop;
    loop.header.frame_id = args.base_frame;
    loop.reference = rrr_slam::LoopClosure::BY_ID;
    loop.from_id = named[e.from].keyframe;
    loop.to_id = named[e.to].keyframe;
    loop.from_stamp = ros::Time(times[e.from]);
    loop.to_stamp = ros::Time(times[e.to]);
    loop.relative_pose.pose = rrr_ros::ToRos(e.measurement);
    loop.relative_pose.covariance =
        rrr_ros::CovarianceFromInformation<Pose>(e.information);
    loop.confidence = -1.0;
    const double time = std::max(times[e.from], times[e.to]) + 1e-6;
    if (named[e.from].robot.empty() && named[e.to].robot.empty()) {
      queue_loop(
          time, args.loop_topic, loop,
          [](rrr_slam::LoopClosure & m) -> auto& { return m.header; });
      continue;
    }
    rrr_slam::FleetLoopClosure fleet_loop;
    fleet_loop.from_robot = named[e.from].robot;
    fleet_loop.to_robot = named[e.to].robot;
    fleet_loop.loop = loop;
    queue_loop(
        time, args.fleet_loop_topic, fleet_loop,
        [](rrr_slam::FleetLoopClosure & m) -> auto& { return m.loop.header; });
  }
  std::stable_sort(
      messages.begin(), messages.end(),
      [](const BagMessage& a, const BagMessage& b) { return a.time < b.time; });

  rosbag::Bag bag;
  try {
    bag.open(args.output, rosbag::bagmode::Write);
  } catch (const rosbag::BagException& e) {
    throw InputError(args.output, 0, e.what());
  }
  for (const BagMessage& message : messages) {
    message.write(bag, ros::Time(message.time));
  }
  bag.close();
  std::set<std::string> robots;
  for (const BagPose& pose : named) robots.insert(pose.robot);
  std::cout << "wrote " << graph.num_poses() << " odometry messages";
  if (spans.size() > 1) {
    std::cout << " of " << robots.size() << " robot"
              << (robots.size() > 1 ? "s (" : " (") << spans.size()
              << " sessions)";
  }
  std::cout << " and " << graph.loops().size() << " loop candidates ("
            << messages.back().time - messages.front().time << " s) to "
            << args.output << "\n";
}

}  // namespace

void AddToBagCommand(CLI::App& app) {
  auto args = std::make_shared<ToBagArgs>();
  CLI::App* cmd = app.add_subcommand("to-bag", kToBagDescription);
  cmd->add_option("input", args->input,
                  "g2o file: one odometry chain with pose ids 0, 1, 2, ..., "
                  "or several (robots as GTSAM symbols, sessions as gaps in "
                  "a robot's ids) for a fleet's node")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--timestamps", args->timestamps, "time of pose k on line k")
      ->check(CLI::ExistingFile);
  cmd->add_option("--rate", args->rate,
                  "odometry rate without --timestamps (Hz)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--odom-topic", args->odom_topic)->capture_default_str();
  cmd->add_option("--loop-topic", args->loop_topic,
                  "loop candidates of a graph of one chain")
      ->capture_default_str();
  cmd->add_option("--fleet-loop-topic", args->fleet_loop_topic,
                  "loop candidates of a graph of several chains "
                  "(rrr_slam/FleetLoopClosure, by robot and keyframe id)")
      ->capture_default_str();
  cmd->add_option("--robot", args->robot,
                  "the robot of the chains whose ids are not GTSAM symbols, "
                  "in a graph of several (each chain a session of it); "
                  "empty: the node's one robot (robots unset), on "
                  "--odom-topic and --loop-topic")
      ->capture_default_str();
  cmd->add_option("--restart-jump", args->restart_jump,
                  "the node's restart_jump: a session whose odometry starts "
                  "again at zero within this of where the robot's previous "
                  "one ended is refused (the node would not see the restart)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
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
    const AnyPoseGraph graph =
        LoadGraph(args->input, false, GraphShape::kAnyChains).graph;
    std::visit([&](const auto& g) { ToBag(g, *args); }, graph);
  });
}

}  // namespace rrr
