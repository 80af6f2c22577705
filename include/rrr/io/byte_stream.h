// A state written as bytes and read back exactly: integers, doubles, poses
// and lists of them, in the byte order of the machine that wrote them (a
// checkpoint is read back by the program that keeps it).
#ifndef RRR_IO_BYTE_STREAM_H_
#define RRR_IO_BYTE_STREAM_H_

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
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
