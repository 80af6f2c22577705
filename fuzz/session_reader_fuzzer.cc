// libFuzzer target: the session database reader on arbitrary files (SQLite
// pages, mostly mutated from real sessions). A read either throws
// SessionError or returns a graph whose loops each have a recorded state.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <variant>

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

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string& path = InputPath();
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) std::abort();
  if (size > 0 && std::fwrite(data, 1, size, f) != size) std::abort();
  std::fclose(f);
  try {
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
