#include "rrr/eval/loop_scores.h"

#include <stdexcept>

namespace rrr {

double LoopScores::precision() const {
  return accepted == 0 ? 1.0 : static_cast<double>(correct_accepted) / accepted;
}

double LoopScores::recall() const {
  return correct_candidates == 0
             ? 1.0
             : static_cast<double>(correct_accepted) / correct_candidates;
}

LoopScores ScoreLoops(const std::vector<bool>& accepted,
                      const std::vector<bool>& correct) {
  if (accepted.size() != correct.size()) {
    throw std::invalid_argument(
        "ScoreLoops: decisions and truth differ in size");
  }
  LoopScores s;
  s.candidates = static_cast<int>(accepted.size());
  for (size_t k = 0; k < accepted.size(); ++k) {
    s.accepted += accepted[k];
    s.correct_candidates += correct[k];
    s.correct_accepted += accepted[k] && correct[k];
  }
  return s;
}

}  // namespace rrr
