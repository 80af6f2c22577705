// Precision and recall of loop-closure decisions.
#ifndef RRR_EVAL_LOOP_SCORES_H_
#define RRR_EVAL_LOOP_SCORES_H_

#include <vector>

namespace rrr {

struct LoopScores {
  int candidates = 0;
  int accepted = 0;
  int correct_candidates = 0;
  int correct_accepted = 0;
  // correct accepted / accepted; 1 when nothing is accepted.
  double precision() const;
  // correct accepted / correct candidates; 1 when there is no correct one.
  double recall() const;
};

// Scores per-candidate decisions against per-candidate truth (same length;
// throws std::invalid_argument otherwise).
LoopScores ScoreLoops(const std::vector<bool>& accepted,
                      const std::vector<bool>& correct);

}  // namespace rrr

#endif  // RRR_EVAL_LOOP_SCORES_H_
