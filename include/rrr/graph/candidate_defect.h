// Loop candidates that cannot be judged, and why.
#ifndef RRR_GRAPH_CANDIDATE_DEFECT_H_
#define RRR_GRAPH_CANDIDATE_DEFECT_H_

#include <stdexcept>
#include <string>

namespace rrr {

// What place recognisers emit that is no usable loop candidate.
enum class CandidateDefect {
  kSelfLoop,          // from a pose to itself
  kConsecutivePoses,  // between consecutive poses (that is odometry)
  kDuplicate,         // the same pair, measurement and information again
  kUnknownPose,       // a pose the graph does not (and cannot) have
  kTooFarAhead,       // a pose further ahead than candidates may wait for
  kWaitingFull,       // as many candidates wait already as may
};
// "self_loop", "consecutive_poses", "duplicate", "unknown_pose",
// "too_far_ahead", "waiting_full".
const char* ToString(CandidateDefect defect);

// Thrown for a degenerate candidate; what() says which candidate and why.
class DegenerateCandidate : public std::invalid_argument {
 public:
  DegenerateCandidate(CandidateDefect defect, const std::string& what)
      : std::invalid_argument(what), defect_(defect) {}
  CandidateDefect defect() const { return defect_; }

 private:
  CandidateDefect defect_;
};

}  // namespace rrr

#endif  // RRR_GRAPH_CANDIDATE_DEFECT_H_
