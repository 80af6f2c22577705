// A one-line progress bar on a terminal; silent otherwise.
#ifndef RRR_TOOLS_PROGRESS_BAR_H_
#define RRR_TOOLS_PROGRESS_BAR_H_

#include <string>

namespace rrr {

// Draws "LABEL [#####     ] done/total" on stderr, redrawn in place, when
// stderr is a terminal and `enabled`; does nothing otherwise.
class ProgressBar {
 public:
  ProgressBar(std::string label, bool enabled);
  ~ProgressBar();
  void Update(int done, int total);

 private:
  std::string label_;
  bool active_;
  bool drawn_ = false;
  int last_permille_ = -1;
};

}  // namespace rrr

#endif  // RRR_TOOLS_PROGRESS_BAR_H_
