// rrr_node: reads its parameters, then runs the verifier node.
#include <ros/ros.h>

#include <memory>
#include <thread>

#include "node_options.h"
#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/solver/process_memory.h"
#include "verifier_node.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "rrr_node");
  if (!rrr::KeepFreedMemory()) {
    ROS_WARN(
        "rrr_node: the allocator keeps no freed memory; whole-map "
        "updates take longer");
  }
  ros::NodeHandle nh, private_nh("~");
  rrr_ros::NodeOptions options;
  try {
    options = rrr_ros::NodeOptions::Read(private_nh);
  } catch (const std::exception& e) {
    ROS_FATAL("rrr_node: %s", e.what());
    return 1;
  }
  // Two threads: services wait for the worker while the other keeps taking
  // messages. The worker is this (the main) thread (VerifierNode::Run).
  ros::AsyncSpinner spinner(2);
  const auto run = [&spinner](auto& node) {
    spinner.start();
    std::thread stop([&node] {
      ros::waitForShutdown();
      node.Stop();
    });
    node.Run();
    stop.join();
  };
  const auto serve = [&](auto pose) {
    rrr_ros::VerifierNode<decltype(pose)> node(nh, private_nh, options);
    run(node);
  };
  try {
    if (options.dimension == 2) {
      serve(rrr::Pose2());
    } else {
      serve(rrr::Pose3());
    }
  } catch (const std::invalid_argument& e) {
    ROS_FATAL("rrr_node: %s", e.what());
    return 1;
  }
  return 0;
}
