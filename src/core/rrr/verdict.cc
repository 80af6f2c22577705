#include "rrr/rrr/verdict.h"

namespace rrr {

Verdict VerdictOf(const std::vector<bool>& accepted) {
  Verdict verdict;
  for (size_t k = 0; k < accepted.size(); ++k) {
    (accepted[k] ? verdict.accepted : verdict.rejected)
        .push_back(static_cast<int>(k));
    verdict.cluster_of_loop.push_back(-1);
  }
  return verdict;
}

}  // namespace rrr
