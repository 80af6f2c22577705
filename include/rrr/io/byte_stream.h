// A state written as bytes and read back exactly: integers, doubles, poses
// and lists of them, in the byte order of the machine that wrote them (a
// checkpoint is read back by the program that keeps it).
//
// ByteWriter and ByteReader share Field and Size, so one function template
// can describe a state for both ways and the two cannot disagree on its
// layout: with a writer it writes each field, with a reader it reads each
// into the same place (`what` names the field in the reader's errors).
#ifndef RRR_IO_BYTE_STREAM_H_
#define RRR_IO_BYTE_STREAM_H_

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace rrr {

// Appends values to a byte string.
class ByteWriter {
 public:
  void Int(std::int64_t value) { Raw(value); }
  void Double(double value) { Raw(value); }
  // A pose, bit for bit (Pose2 and Pose3 parts()).
  template <class Pose>
  void PoseParts(const Pose& pose) {
    for (const double v : pose.parts()) Double(v);
  }
  // A count, then each value in 32 bits.
  void Ints(const std::vector<int>& values) {
    Int(static_cast<std::int64_t>(values.size()));
    for (const int v : values) Raw(static_cast<std::int32_t>(v));
  }
  void Doubles(const std::vector<double>& values) {
    Int(static_cast<std::int64_t>(values.size()));
    for (const double v : values) Double(v);
  }
  void Text(const std::string& text) {
    Int(static_cast<std::int64_t>(text.size()));
    bytes_ += text;
  }
  // An integer, bool, enum, double, text or list of ints or doubles.
  template <class T>
  void Field(const T* value, const char* /*what*/) {
    if constexpr (std::is_same_v<T, std::vector<int>>) {
      Ints(*value);
    } else if constexpr (std::is_same_v<T, std::vector<double>>) {
      Doubles(*value);
    } else if constexpr (std::is_same_v<T, std::string>) {
      Text(*value);
    } else if constexpr (std::is_floating_point_v<T>) {
      Double(*value);
    } else {
      Int(static_cast<std::int64_t>(*value));
    }
  }
  // An enum whose values run from 0 to `last`.
  template <class Enum>
  void Field(const Enum* value, const char* what, Enum /*last*/) {
    Field(value, what);
  }
  // The number of `items`, which the fields that follow describe.
  template <class T>
  void Size(const std::vector<T>* items, size_t /*item_bytes*/,
            const char* /*what*/) {
    Int(static_cast<std::int64_t>(items->size()));
  }
  const std::string& bytes() const { return bytes_; }

 private:
  template <class T>
  void Raw(const T& value) {
    char raw[sizeof(T)];
    std::memcpy(raw, &value, sizeof(T));
    bytes_.append(raw, sizeof(T));
  }

  std::string bytes_;
};

// Reads what a ByteWriter wrote, in the same order. Every read throws
// std::runtime_error naming what it read if the bytes end before it or a
// count is negative or larger than the bytes left could hold.
class ByteReader {
 public:
  explicit ByteReader(const std::string& bytes) : bytes_(bytes) {}

  std::int64_t Int(const char* what) { return Raw<std::int64_t>(what); }
  double Double(const char* what) { return Raw<double>(what); }
  template <class Pose>
  Pose PoseParts(const char* what) {
    typename Pose::Parts parts;
    for (double& v : parts) v = Double(what);
    return Pose::FromParts(parts);
  }
  // A count of items of at least `item_bytes` bytes each that follow.
  size_t Count(const char* what, size_t item_bytes) {
    const std::int64_t n = Int(what);
    if (n < 0 ||
        static_cast<std::uint64_t>(n) >
            (bytes_.size() - next_) / std::max<size_t>(item_bytes, 1)) {
      throw std::runtime_error(std::string(what) + ": count " +
                               std::to_string(n) + " does not fit the state");
    }
    return static_cast<size_t>(n);
  }
  std::vector<int> Ints(const char* what) {
    std::vector<int> values(Count(what, sizeof(std::int32_t)));
    for (int& v : values) v = Raw<std::int32_t>(what);
    return values;
  }
  std::vector<double> Doubles(const char* what) {
    std::vector<double> values(Count(what, sizeof(double)));
    for (double& v : values) v = Double(what);
    return values;
  }
  std::string Text(const char* what) {
    const size_t n = Count(what, 1);
    std::string text = bytes_.substr(next_, n);
    next_ += n;
    return text;
  }
  // What ByteWriter::Field wrote of `*value`'s type, into `*value`.
  template <class T>
  void Field(T* value, const char* what) {
    static_assert(!std::is_enum_v<T>, "an enum is read with its last value");
    if constexpr (std::is_same_v<T, std::vector<int>>) {
      *value = Ints(what);
    } else if constexpr (std::is_same_v<T, std::vector<double>>) {
      *value = Doubles(what);
    } else if constexpr (std::is_same_v<T, std::string>) {
      *value = Text(what);
    } else if constexpr (std::is_floating_point_v<T>) {
      *value = Double(what);
    } else if constexpr (std::is_same_v<T, bool>) {
      *value = Int(what) != 0;
    } else {
      *value = static_cast<T>(Int(what));
    }
  }
  // An enum value from 0 to `last`; throws std::runtime_error naming `what`
  // if it is out of that range.
  template <class Enum>
  void Field(Enum* value, const char* what, Enum last) {
    const std::int64_t v = Int(what);
    if (v < 0 || v > static_cast<std::int64_t>(last)) {
      throw std::runtime_error(std::string(what) + " has the unknown value " +
                               std::to_string(v));
    }
    *value = static_cast<Enum>(v);
  }
  // Resizes `*items` to the count that follows (see Count).
  template <class T>
  void Size(std::vector<T>* items, size_t item_bytes, const char* what) {
    items->resize(Count(what, item_bytes));
  }
  bool AtEnd() const { return next_ == bytes_.size(); }

 private:
  template <class T>
  T Raw(const char* what) {
    if (bytes_.size() - next_ < sizeof(T)) {
      throw std::runtime_error(std::string("the state ends before ") + what);
    }
    T value;
    std::memcpy(static_cast<void*>(&value), bytes_.data() + next_, sizeof(T));
    next_ += sizeof(T);
    return value;
  }

  const std::string& bytes_;
  size_t next_ = 0;
};

}  // namespace rrr

#endif  // RRR_IO_BYTE_STREAM_H_
