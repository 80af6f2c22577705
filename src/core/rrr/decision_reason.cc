#include "rrr/rrr/decision_reason.h"

namespace rrr {

const char* ToString(DecisionTest test) {
  switch (test) {
    case DecisionTest::kNotJudged:
      return "not_judged";
    case DecisionTest::kAlone:
      return "alone";
    case DecisionTest::kOwnLink:
      return "own_link";
    case DecisionTest::kOwn:
      return "own";
    case DecisionTest::kMapLink:
      return "map_link";
    case DecisionTest::kMap:
      return "map";
    case DecisionTest::kOutweighed:
      return "outweighed";
    case DecisionTest::kJoin:
      return "join";
    case DecisionTest::kApart:
      return "apart";
  }
  return "unknown";
}

}  // namespace rrr
