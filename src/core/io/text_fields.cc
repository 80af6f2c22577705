#include "rrr/io/text_fields.h"

#include <algorithm>
#include <charconv>
#include <cmath>

#include "rrr/io/input_error.h"

namespace rrr {
namespace {

// Whether `c` is white space in the "C" locale.
bool IsSpace(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' ||
         c == '\f';
}

// Reads all of `field` into `*value` by std::from_chars, which takes no
// leading '+' where strtod and strtoll do: one is skipped before a digit or
// a point. Returns false unless all of it is read and in range.
template <class T>
bool ReadAll(std::string_view field, T* value) {
  const char* first = field.data();
  const char* last = first + field.size();
  if (field.size() > 1 && field[0] == '+' && field[1] != '-' &&
      field[1] != '+') {
    ++first;
  }
  const auto [end, error] = std::from_chars(first, last, *value);
  return error == std::errc() && end == last;
}

}  // namespace

TextFields::TextFields(std::string_view text, std::string_view source, int line,
                       bool commas_separate)
    : source_(source), line_(line) {
  const auto separates = [&](char c) {
    return IsSpace(c) || (commas_separate && c == ',');
  };
  for (auto it = text.begin(); it != text.end();) {
    const auto first = std::find_if_not(it, text.end(), separates);
    it = std::find_if(first, text.end(), separates);
    if (first != it) {
      fields_.emplace_back(&*first, static_cast<size_t>(it - first));
    }
  }
}

void TextFields::ExpectCount(size_t n, const std::string& what) const {
  if (fields_.size() != n) {
    Fail(what + " needs " + std::to_string(n) + " fields, found " +
         std::to_string(fields_.size()));
  }
}

void TextFields::ExpectAtLeast(size_t n, const std::string& what) const {
  if (fields_.size() < n) {
    Fail(what + " needs at least " + std::to_string(n) + " fields, found " +
         std::to_string(fields_.size()));
  }
}

double TextFields::Number(size_t k) const {
  const std::string_view f = fields_.at(k);
  double v = 0.0;
  if (!ReadAll(f, &v)) {
    Fail("field " + std::to_string(k) + " '" + std::string(f) +
         "' is not a number");
  }
  if (!std::isfinite(v)) {
    Fail("field " + std::to_string(k) + " '" + std::string(f) +
         "' is not finite");
  }
  return v;
}

std::int64_t TextFields::Integer(size_t k) const {
  const std::string_view f = fields_.at(k);
  std::int64_t v = 0;
  if (!ReadAll(f, &v)) {
    Fail("field " + std::to_string(k) + " '" + std::string(f) +
         "' is not an integer id");
  }
  return v;
}

std::vector<double> TextFields::Numbers(size_t first) const {
  std::vector<double> v;
  v.reserve(fields_.size() - std::min(first, fields_.size()));
  for (size_t k = first; k < fields_.size(); ++k) v.push_back(Number(k));
  return v;
}

void TextFields::Fail(const std::string& problem) const {
  throw InputError(std::string(source_), line_, problem);
}

}  // namespace rrr
