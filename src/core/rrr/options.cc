#include "rrr/rrr/options.h"

namespace rrr {

std::string RrrOptions::Validate() const {
  if (cluster_window < 1) {
    return "cluster_window must be at least 1, got " +
           std::to_string(cluster_window);
  }
  if (iterations < 1) {
    return "iterations must be at least 1, got " + std::to_string(iterations);
  }
  if (!(alpha > 0.0 && alpha < 1.0)) {
    return "alpha must be in (0, 1), got " + std::to_string(alpha);
  }
  if (threads < 1) {
    return "threads must be at least 1, got " + std::to_string(threads);
  }
  if (max_future_poses < 0) {
    return "max_future_poses must not be negative, got " +
           std::to_string(max_future_poses);
  }
  if (decision_delay < 0) {
    return "decision_delay must not be negative, got " +
           std::to_string(decision_delay);
  }
  if (max_waiting < 0) {
    return "max_waiting must not be negative, got " +
           std::to_string(max_waiting);
  }
  if (!(noise_scale >= 0.0)) {
    return "noise_scale must be positive, or 0 to estimate it, got " +
           std::to_string(noise_scale);
  }
  if (!(noise_margin > 0.0)) {
    return "noise_margin must be positive, got " + std::to_string(noise_margin);
  }
  if (map_radius < 1) {
    return "map_radius must be at least 1, got " + std::to_string(map_radius);
  }
  if (map_junctions < 1) {
    return "map_junctions must be at least 1, got " +
           std::to_string(map_junctions);
  }
  if (optimize_every < 1) {
    return "optimize_every must be at least 1, got " +
           std::to_string(optimize_every);
  }
  if (!(optimize_growth >= 0.0)) {
    return "optimize_growth must not be negative, got " +
           std::to_string(optimize_growth);
  }
  if (convergence.max_iterations < 1) {
    return "the iteration limit must be at least 1, got " +
           std::to_string(convergence.max_iterations);
  }
  return "";
}

const char* ToString(Procedure procedure) {
  return procedure == Procedure::kMap ? "map" : "published";
}

bool ParseProcedure(const std::string& name, Procedure* procedure) {
  if (name == "published") {
    *procedure = Procedure::kPublished;
  } else if (name == "map") {
    *procedure = Procedure::kMap;
  } else {
    return false;
  }
  return true;
}

}  // namespace rrr
