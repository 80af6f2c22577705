// A session database of rrr_node replayed for a command.
#ifndef RRR_TOOLS_SESSION_FILE_H_
#define RRR_TOOLS_SESSION_FILE_H_

#include <unistd.h>

#include <filesystem>
#include <string>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/rrr/options.h"
#include "rrr/session/session.h"

namespace rrr {

// Replays the session database at `path` (ReplaySession under `options`, or
// under the options it recorded if null, in a temporary copy removed
// afterwards) and calls `use` with the session, of the dimension it was
// recorded in.
// Throws SessionError naming the file if it cannot be replayed.
template <class Use>
void WithSessionDatabase(const std::string& path, const RrrOptions* options,
                         const Use& use) {
  const SessionDatabase recorded = ReadSessionDatabase(path);
  SessionOptions session;
  session.rrr = options ? *options : recorded.options;
  const std::string copy =
      (std::filesystem::temp_directory_path() /
       ("rrr_replay_" + std::to_string(::getpid()) + ".db"))
          .string();
  const struct Remove {
    const std::string& copy;
    ~Remove() {
      std::error_code ignored;
      for (const char* part : {"", "-wal", "-shm"}) {
        std::filesystem::remove(copy + part, ignored);
      }
    }
  } remove{copy};
  if (recorded.dimension == 2) {
    use(*ReplaySession<Pose2>(path, copy, session));
  } else {
    use(*ReplaySession<Pose3>(path, copy, session));
  }
}

}  // namespace rrr

#endif  // RRR_TOOLS_SESSION_FILE_H_
