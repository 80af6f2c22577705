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
  return "";
}

}  // namespace rrr
