// libFuzzer target: the session database reader and resume on arbitrary
// files (SQLite pages, mostly mutated from real sessions). Reading either
// throws SessionError or names the robots, dimension and options; a
// session of those robots resumed on the file then either throws
// SessionError or holds every keyframe and candidate it counted.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/session/session.h"
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

// Resumes the database at `path`, recorded as `recorded` says.
template <class Pose>
void Resume(const std::string& path, const rrr::SessionDatabase& recorded) {
  rrr::SessionOptions options;
  options.rrr = recorded.options;
  options.database = path;
  rrr::Session<Pose> session(recorded.robots, options, nullptr);
  const rrr::ResumeSummary summary = session.Resume();
  if (session.num_keyframes() != summary.keyframes ||
      session.verifier().num_candidates() > summary.candidates ||
      summary.differing_decisions < 0) {
    std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string& path = InputPath();
  for (const char* part : {"-wal", "-shm"}) std::remove((path + part).c_str());
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) std::abort();
  if (size > 0 && std::fwrite(data, 1, size, f) != size) std::abort();
  std::fclose(f);
  try {
    const rrr::SessionDatabase recorded = rrr::ReadSessionDatabase(path);
    if (recorded.dimension == 2) {
      Resume<rrr::Pose2>(path, recorded);
    } else {
      Resume<rrr::Pose3>(path, recorded);
    }
  } catch (const rrr::SessionError&) {
    // A clear refusal is a correct answer.
  }
  return 0;
}
