// One line of a text input split into fields, with checked number parsing.
#ifndef RRR_IO_TEXT_FIELDS_H_
#define RRR_IO_TEXT_FIELDS_H_

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace rrr {

// Splits `text` at whitespace (and commas, if `commas_separate`). The fields
// are views into `text`, which must outlive this object, as must `source`.
// Every accessor that fails throws InputError naming `source` and `line`.
class TextFields {
 public:
  TextFields(std::string_view text, std::string_view source, int line,
             bool commas_separate = false);

  size_t size() const { return fields_.size(); }
  bool empty() const { return fields_.empty(); }
  // Blank lines and lines starting with '#' are comments.
  bool IsComment() const { return empty() || fields_[0][0] == '#'; }
  std::string_view operator[](size_t k) const { return fields_.at(k); }

  // Throws unless there are exactly `n` fields, naming `what` in the message.
  void ExpectCount(size_t n, const std::string& what) const;
  // Throws unless there are at least `n` fields.
  void ExpectAtLeast(size_t n, const std::string& what) const;
  // Field k as a finite double, read as strtod reads a decimal number and
  // rounded as it rounds; throws naming the field otherwise.
  double Number(size_t k) const;
  // Field k as an integer id.
  std::int64_t Integer(size_t k) const;
  // Fields first..end as finite doubles.
  std::vector<double> Numbers(size_t first) const;
  [[noreturn]] void Fail(const std::string& problem) const;

 private:
  std::vector<std::string_view> fields_;
  std::string_view source_;
  int line_;
};

}  // namespace rrr

#endif  // RRR_IO_TEXT_FIELDS_H_
