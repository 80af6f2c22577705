#include "node_options.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace rrr_ros {
namespace {

[[noreturn]] void Bad(const ros::NodeHandle& nh, const std::string& name,
                      const std::string& why) {
  throw std::invalid_argument("parameter " + nh.resolveName(name) + ": " + why);
}

// Names from "[a, b]" or "a,b" (as `_robots:=[a, b]` on rosrun's command
// line arrives: roscpp sets such a parameter as a string).
std::vector<std::string> NamesOf(const std::string& text) {
  std::vector<std::string> names;
  std::string name;
  for (const char c : text + ",") {
    if (c == ',') {
      names.push_back(name);
      name.clear();
    } else if (c != '[' && c != ']' && c != ' ' && c != '\'' && c != '"') {
      name += c;
    }
  }
  if (names.size() == 1 && names[0].empty()) names.clear();
  return names;
}

}  // namespace

NodeOptions NodeOptions::Read(const ros::NodeHandle& nh) {
  NodeOptions o;
  nh.param("dimension", o.dimension, o.dimension);
  if (o.dimension != 2 && o.dimension != 3)
    Bad(nh, "dimension", "must be 2 or 3");
  nh.param("map_frame", o.map_frame, o.map_frame);
  nh.param("odom_frame", o.odom_frame, o.odom_frame);
  nh.param("base_frame", o.base_frame, o.base_frame);
  for (const auto& [name, frame] : {std::pair{"map_frame", &o.map_frame},
                                    {"odom_frame", &o.odom_frame},
                                    {"base_frame", &o.base_frame}}) {
    if (frame->empty()) Bad(nh, name, "must not be empty");
  }
  if (o.map_frame == o.odom_frame)
    Bad(nh, "map_frame", "must differ from odom_frame");
  rrr::OdometryInputOptions& odometry = o.odometry;
  nh.param("keyframe/translation", odometry.keyframe_translation,
           odometry.keyframe_translation);
  nh.param("keyframe/rotation", odometry.keyframe_rotation,
           odometry.keyframe_rotation);
  if (!(odometry.keyframe_translation >= 0))
    Bad(nh, "keyframe/translation", "must be >= 0");
  if (!(odometry.keyframe_rotation >= 0))
    Bad(nh, "keyframe/rotation", "must be >= 0");
  nh.param("odometry/use_covariance", odometry.use_odometry_covariance,
           odometry.use_odometry_covariance);
  const size_t dof = o.dimension == 2 ? 3 : 6;
  odometry.odometry_information.assign(dof, 100.0);
  nh.param("odometry/information", odometry.odometry_information,
           odometry.odometry_information);
  if (odometry.odometry_information.size() != dof) {
    Bad(nh, "odometry/information",
        "needs " + std::to_string(dof) + " values (the diagonal)");
  }
  for (const double v : odometry.odometry_information) {
    if (!(v > 0 && std::isfinite(v))) {
      Bad(nh, "odometry/information", "values must be positive and finite");
    }
  }
  nh.param("odometry/min_motion", odometry.odometry_min_motion,
           odometry.odometry_min_motion);
  if (!(odometry.odometry_min_motion > 0 &&
        std::isfinite(odometry.odometry_min_motion))) {
    Bad(nh, "odometry/min_motion", "must be positive and finite");
  }
  double stamp_tolerance = odometry.stamp_tolerance_ns * 1e-9;
  nh.param("stamp_tolerance", stamp_tolerance, stamp_tolerance);
  if (!(stamp_tolerance >= 0 && stamp_tolerance < 1e9))
    Bad(nh, "stamp_tolerance", "must be >= 0 (s) and below 1e9");
  odometry.stamp_tolerance_ns = std::llround(stamp_tolerance * 1e9);
  nh.param("tf_period", o.tf_period, o.tf_period);
  if (!(o.tf_period > 0)) Bad(nh, "tf_period", "must be > 0");
  nh.param("display_period", o.display_period, o.display_period);
  if (!(o.display_period >= 0)) Bad(nh, "display_period", "must be >= 0");
  nh.param("graph_period", o.graph_period, o.graph_period);
  if (!(o.graph_period >= 0)) Bad(nh, "graph_period", "must be >= 0");
  int max_queue = static_cast<int>(o.max_queue_length);
  nh.param("max_queue_length", max_queue, max_queue);
  if (max_queue < 1) Bad(nh, "max_queue_length", "must be at least 1");
  o.max_queue_length = static_cast<size_t>(max_queue);
  nh.param("max_future_keyframes", o.rrr.max_future_poses,
           o.rrr.max_future_poses);
  nh.param("max_waiting", o.rrr.max_waiting, o.rrr.max_waiting);
  nh.param("decision_delay", o.rrr.decision_delay, o.rrr.decision_delay);
  nh.param("cluster_window", o.rrr.cluster_window, o.rrr.cluster_window);
  nh.param("iterations", o.rrr.iterations, o.rrr.iterations);
  nh.param("alpha", o.rrr.alpha, o.rrr.alpha);
  nh.param("span_gate", o.rrr.span_gate, o.rrr.span_gate);
  nh.param("threads", o.rrr.threads, o.rrr.threads);
  bool trust_region = o.rrr.steps == rrr::SolveSteps::kTrustRegion;
  nh.param("trust_region", trust_region, trust_region);
  o.rrr.steps = trust_region ? rrr::SolveSteps::kTrustRegion
                             : rrr::SolveSteps::kGaussNewton;
  std::string procedure = rrr::ToString(o.rrr.procedure);
  nh.param("procedure", procedure, procedure);
  if (!rrr::ParseProcedure(procedure, &o.rrr.procedure)) {
    Bad(nh, "procedure",
        "must be 'map' or 'published', got '" + procedure + "'");
  }
  nh.param("database", o.database, o.database);
  nh.param("checkpoint_keyframes", o.checkpoint_keyframes,
           o.checkpoint_keyframes);
  if (o.checkpoint_keyframes < 0) {
    Bad(nh, "checkpoint_keyframes", "must be >= 0");
  }
  nh.param("noise_scale", o.rrr.noise_scale, o.rrr.noise_scale);
  nh.param("noise_margin", o.rrr.noise_margin, o.rrr.noise_margin);
  nh.param("map_radius", o.rrr.map_radius, o.rrr.map_radius);
  nh.param("map_junctions", o.rrr.map_junctions, o.rrr.map_junctions);
  std::string robots;
  if (nh.getParam("robots", robots)) {
    o.robots = NamesOf(robots);
  } else {
    nh.param("robots", o.robots, o.robots);
  }
  for (size_t r = 0; r < o.robots.size(); ++r) {
    const std::string& name = o.robots[r];
    if (name.empty() || name.find_first_of("/ ") != std::string::npos ||
        std::count(o.robots.begin(), o.robots.end(), name) > 1) {
      Bad(nh, "robots",
          "robot " + std::to_string(r) + " ('" + name +
              "') must be a unique, non-empty name without '/' or spaces");
    }
  }
  if (!o.robots.empty() && o.rrr.procedure != rrr::Procedure::kMap) {
    Bad(nh, "procedure", "a fleet (robots set) is judged by 'map' only");
  }
  nh.param("restart_jump", o.restart_jump, o.restart_jump);
  if (!(o.restart_jump >= 0)) Bad(nh, "restart_jump", "must be >= 0");
  const std::string problem = o.rrr.Validate();
  if (!problem.empty()) {
    Bad(nh, problem.substr(0, problem.find(' ')), problem);
  }
  return o;
}

}  // namespace rrr_ros
