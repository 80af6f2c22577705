#include "rrr/io/text_fields.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>

#include "rrr/io/input_error.h"

namespace rrr {

TextFields::TextFields(const std::string& text, const std::string& source,
                       int line, bool commas_separate)
    : source_(source), line_(line) {
  const auto separates = [&](char c) {
    return std::isspace(static_cast<unsigned char>(c)) ||
           (commas_separate && c == ',');
  };
  for (auto it = text.begin(); it != text.end();) {
    const auto first = std::find_if_not(it, text.end(), separates);
    it = std::find_if(first, text.end(), separates);
    if (first != it) fields_.emplace_back(first, it);
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
  const std::string& f = fields_.at(k);
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(f.c_str(), &end);
  if (end == f.c_str() || *end != '\0' || errno == ERANGE) {
    Fail("field " + std::to_string(k) + " '" + f + "' is not a number");
  }
  if (!std::isfinite(v)) {
    Fail("field " + std::to_string(k) + " '" + f + "' is not finite");
  }
  return v;
}

std::int64_t TextFields::Integer(size_t k) const {
  const std::string& f = fields_.at(k);
  errno = 0;
  char* end = nullptr;
  const long long v = std::strtoll(f.c_str(), &end, 10);
  if (end == f.c_str() || *end != '\0' || errno == ERANGE) {
    Fail("field " + std::to_string(k) + " '" + f + "' is not an integer id");
  }
  return v;
}

std::vector<double> TextFields::Numbers(size_t first) const {
  std::vector<double> v;
  for (size_t k = first; k < fields_.size(); ++k) v.push_back(Number(k));
  return v;
}

void TextFields::Fail(const std::string& problem) const {
  throw InputError(source_, line_, problem);
}

}  // namespace rrr
