// libFuzzer target: the session database readers on arbitrary files (SQLite
// pages, mostly mutated from real sessions): a robot's session read as a
// graph, a fleet's resumed into a fleet. A read either throws SessionError
// or returns a graph whose loops each have a recorded state; a resume either
// throws SessionError or gives a fleet with the keyframes it counted.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <variant>

#include "rrr/fleet/fleet.h"
#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/session/fleet_store.h"
#include "rrr/session/session_store.h"

namespace {

// One file per fuzzing process, rewritten for each input.
const std::string& InputPath() {
  static const std::string path = [] {
    char name[] = "/tmp/rrr_session_fuzz_XXXXXX";
    const int fd = mkstemp(name);
    if (fd < 0) std::abort();
    close(fd);
    return std::string(name);
  }();
  return path;
}

// Resumes the fleet's database at `path` into a fleet of robots a and b.
template <class Pose>
void ResumeFleet(const std::string& path) {
  rrr::Fleet<Pose> fleet({"a", "b"}, rrr::FleetOptions{});
  rrr::FleetStore<Pose> store(path, {"a", "b"}, "map");
  const rrr::FleetResumeSummary summary = store.Resume(&fleet);
  if (fleet.verifier().graph().num_poses() != summary.keyframes ||
      summary.differing_decisions < 0) {
    std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string& path = InputPath();
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) std::abort();
  if (size > 0 && std::fwrite(data, 1, size, f) != size) std::abort();
  std::fclose(f);
  try {
    if (rrr::IsFleetDatabase(path)) {
      try {
        ResumeFleet<rrr::Pose2>(path);
      } catch (const rrr::SessionError&) {
        ResumeFleet<rrr::Pose3>(path);  // or it is a 3D one
      }
      return 0;
    }
    const rrr::SessionContents session = rrr::ReadSession(path);
    const size_t loops = std::visit(
        [](const auto& g) { return g.loops().size(); }, session.graph);
    if (session.loop_states.size() != loops || session.updates < 0 ||
        session.candidates_waiting < 0) {
      std::abort();
    }
  } catch (const rrr::SessionError&) {
    // A clear refusal is a correct answer.
  }
  return 0;
}
