// rrr_node's status as its users read it: the counters of ~get_status by
// reason, and the /diagnostics message made from them.
#ifndef RRR_ROS_STATUS_MESSAGES_H_
#define RRR_ROS_STATUS_MESSAGES_H_

#include <diagnostic_msgs/DiagnosticArray.h>

#include <cstdint>
#include <string>

#include "rrr/graph/candidate_defect.h"
#include "rrr/session/session.h"
#include "rrr_slam/GetStatus.h"

namespace rrr_ros {

// Sets the fields of `status` that describe `session`: keyframes, sessions
// and maps, candidates by state, those waiting for a keyframe or a robot,
// clusters and the noise scale with its source.
template <class Pose>
void SetSessionState(const rrr::Session<Pose>& session,
                     rrr_slam::GetStatus::Response* status);

// Counts one skipped or refused candidate under its reason in `status`.
void CountCandidateDefect(rrr::CandidateDefect defect,
                          rrr_slam::GetStatus::Response* status);
// Candidates skipped or refused so far, over every reason.
uint64_t CandidateDefects(const rrr_slam::GetStatus::Response& status);

// The /diagnostics array for `status` of node `node_name`: WARN while
// invalid messages were ignored or inputs refused (by a bound or at the
// queue), else OK, with the main counters as values.
diagnostic_msgs::DiagnosticArray DiagnosticsOf(
    const rrr_slam::GetStatus::Response& status, const std::string& node_name);

}  // namespace rrr_ros

#endif  // RRR_ROS_STATUS_MESSAGES_H_
