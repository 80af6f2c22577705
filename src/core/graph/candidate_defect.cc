#include "rrr/graph/candidate_defect.h"

namespace rrr {

const char* ToString(CandidateDefect defect) {
  switch (defect) {
    case CandidateDefect::kSelfLoop:
      return "self_loop";
    case CandidateDefect::kConsecutivePoses:
      return "consecutive_poses";
    case CandidateDefect::kDuplicate:
      return "duplicate";
    case CandidateDefect::kUnknownPose:
      return "unknown_pose";
    case CandidateDefect::kTooFarAhead:
      return "too_far_ahead";
    case CandidateDefect::kWaitingFull:
      return "waiting_full";
  }
  return "unknown";
}

}  // namespace rrr
