// The error raised for bad input, carrying where the input came from.
#ifndef RRR_IO_INPUT_ERROR_H_
#define RRR_IO_INPUT_ERROR_H_

#include <stdexcept>
#include <string>

namespace rrr {

// Bad input: what() reads "SOURCE:LINE: PROBLEM" (or "SOURCE: PROBLEM" when
// the problem has no line), so it can be shown to the user as it is.
class InputError : public std::runtime_error {
 public:
  InputError(const std::string& source, int line, const std::string& problem)
      : std::runtime_error(source +
                           (line > 0 ? ":" + std::to_string(line) : "") + ": " +
                           problem) {}
};

}  // namespace rrr

#endif  // RRR_IO_INPUT_ERROR_H_
