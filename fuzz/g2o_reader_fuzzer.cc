// libFuzzer target: the g2o reader on arbitrary text, strict and lenient.
// A parse either throws InputError or returns a graph whose every edge names
// poses it has, with finite measurements and information.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>
#include <variant>

#include "rrr/io/g2o.h"
#include "rrr/io/input_error.h"

namespace {

template <class Pose>
void CheckGraph(const rrr::PoseGraph<Pose>& g) {
  if (g.num_poses() <= 0) std::abort();
  const auto check = [&](const rrr::Constraint<Pose>& e) {
    if (e.from < 0 || e.to < 0 || e.from >= g.num_poses() ||
        e.to >= g.num_poses() || !e.information.allFinite() ||
        !e.measurement.Log().allFinite()) {
      std::abort();
    }
  };
  for (const auto& e : g.odometry()) check(e);
  for (const auto& e : g.loops()) check(e);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  for (const bool strict : {false, true}) {
    std::istringstream in(text);
    try {
      const rrr::G2oFile file = rrr::ParseG2o(in, "fuzz input", strict);
      std::visit([](const auto& g) { CheckGraph(g); }, file.graph);
    } catch (const rrr::InputError&) {
      // A clear refusal is a correct answer.
    }
  }
  return 0;
}
