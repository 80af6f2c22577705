// Pose ids written as GTSAM symbols: a robot's letter in the top byte, the
// pose's index in the lower 56 bits (as the Kimera-Multi and distributed
// pose-graph datasets write multi-robot g2o files).
#ifndef RRR_IO_SYMBOL_KEY_H_
#define RRR_IO_SYMBOL_KEY_H_

#include <cctype>
#include <optional>

#include "rrr/graph/pose_graph.h"

namespace rrr {

struct SymbolKey {
  char robot;
  PoseId index;
};

// The symbol `id` is, if its top byte is a letter; ids of one robot then
// follow each other, so its odometry is an odometry chain as any other.
inline std::optional<SymbolKey> AsSymbol(PoseId id) {
  constexpr int kIndexBits = 56;
  const PoseId top = id >> kIndexBits;
  if (id < 0 || !std::isalpha(static_cast<int>(top))) return std::nullopt;
  return SymbolKey{static_cast<char>(top),
                   id & ((PoseId{1} << kIndexBits) - 1)};
}

}  // namespace rrr

#endif  // RRR_IO_SYMBOL_KEY_H_
