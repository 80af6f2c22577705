// libFuzzer target: the map procedure's saved state (MapVerifier::SaveState,
// what a session's checkpoint holds), mutated from the one make_seeds saves,
// restored into a verifier given the same inputs. RestoreState either throws
// std::runtime_error or gives a verifier that finishes (judges what is
// pending, minimizes the whole map, arbitrates) and saves its state again.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "../src/core/testing/feed_poses.h"
#include "../src/core/testing/small_ring.h"
#include "rrr/geometry/pose2.h"
#include "rrr/rrr/map/map_verifier.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const rrr::PoseGraph<rrr::Pose2>& world = rrr::testing::SmallRing().graph;
  rrr::MapVerifier<rrr::Pose2> verifier{rrr::RrrOptions()};
  rrr::testing::FeedPoses(world, 0, rrr::testing::kSmallRingSavedPoses,
                          &verifier);
  try {
    verifier.RestoreState(
        std::string(reinterpret_cast<const char*>(data), size));
  } catch (const std::runtime_error&) {
    return 0;  // a clear refusal is a correct answer
  }
  verifier.Finish();
  verifier.SaveState();
  return 0;
}
