#include "status_messages.h"

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"

namespace rrr_ros {

template <class Pose>
void SetSessionState(const rrr::Session<Pose>& session,
                     rrr_slam::GetStatus::Response* status) {
  const rrr::OnlineVerifier<Pose>& verifier = session.verifier();
  status->keyframes = verifier.graph().num_poses();
  status->sessions = session.num_chains();
  status->maps = 0;
  for (int c = 0; c < session.num_chains(); ++c) {
    status->maps += session.MapOfChain(c) == c;
  }
  status->candidates = verifier.num_candidates();
  status->accepted = verifier.num_in_state(rrr::LoopState::kAccepted);
  status->rejected = verifier.num_in_state(rrr::LoopState::kRejected);
  status->pending = verifier.num_in_state(rrr::LoopState::kPending);
  status->waiting_by_stamp = session.num_waiting_by_stamp();
  status->waiting = verifier.num_waiting() + session.num_waiting_for_robots() +
                    status->waiting_by_stamp;
  status->clusters = verifier.num_clusters();
  status->noise_scale = verifier.noise_scale();
  status->noise_scale_source = verifier.noise_scale_source();
  status->group_noise_scale = verifier.group_noise_scale();
}

template void SetSessionState(const rrr::Session<rrr::Pose2>&,
                              rrr_slam::GetStatus::Response*);
template void SetSessionState(const rrr::Session<rrr::Pose3>&,
                              rrr_slam::GetStatus::Response*);

void CountCandidateDefect(rrr::CandidateDefect defect,
                          rrr_slam::GetStatus::Response* status) {
  switch (defect) {
    case rrr::CandidateDefect::kSelfLoop:
      ++status->skipped_self_loops;
      break;
    case rrr::CandidateDefect::kConsecutivePoses:
      ++status->skipped_consecutive_poses;
      break;
    case rrr::CandidateDefect::kDuplicate:
      ++status->skipped_duplicates;
      break;
    case rrr::CandidateDefect::kUnknownPose:
      ++status->skipped_unknown_poses;
      break;
    case rrr::CandidateDefect::kTooFarAhead:
      ++status->refused_too_far_ahead;
      break;
    case rrr::CandidateDefect::kWaitingFull:
      ++status->refused_waiting_full;
      break;
  }
}

uint64_t CandidateDefects(const rrr_slam::GetStatus::Response& status) {
  return status.skipped_self_loops + status.skipped_consecutive_poses +
         status.skipped_duplicates + status.skipped_unknown_poses +
         status.refused_too_far_ahead + status.refused_waiting_full;
}

diagnostic_msgs::DiagnosticArray DiagnosticsOf(
    const rrr_slam::GetStatus::Response& s, const std::string& node_name) {
  diagnostic_msgs::DiagnosticStatus status;
  status.name = node_name + ": loop-closure verification";
  status.hardware_id = "rrr_slam";
  const uint64_t refused =
      s.refused_too_far_ahead + s.refused_waiting_full + s.inputs_refused;
  status.level = s.invalid_messages > 0 || refused > 0
                     ? diagnostic_msgs::DiagnosticStatus::WARN
                     : diagnostic_msgs::DiagnosticStatus::OK;
  status.message = s.invalid_messages > 0 && refused > 0
                       ? "invalid messages ignored, inputs refused"
                   : s.invalid_messages > 0 ? "invalid messages ignored"
                   : refused > 0            ? "inputs refused"
                                            : "ok";
  const auto add = [&status](const std::string& key, double value) {
    diagnostic_msgs::KeyValue kv;
    kv.key = key;
    kv.value = std::to_string(value);
    status.values.push_back(kv);
  };
  add("keyframes", s.keyframes);
  add("candidates", s.candidates);
  add("accepted", s.accepted);
  add("rejected", s.rejected);
  add("pending", s.pending);
  add("waiting for a keyframe", s.waiting);
  add("queue length", s.queue_length);
  add("max queue length", s.max_queue_length);
  add("last update (s)", s.last_update_seconds);
  add("invalid messages", s.invalid_messages);
  add("skipped or refused candidates", CandidateDefects(s));
  add("inputs refused at the queue", s.inputs_refused);
  diagnostic_msgs::DiagnosticArray array;
  array.header.stamp = ros::Time::now();
  array.status.push_back(status);
  return array;
}

}  // namespace rrr_ros
