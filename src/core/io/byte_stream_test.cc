// One description of a state, written and read back through Field and Size.
#include "rrr/io/byte_stream.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace rrr {
namespace {

enum class Colour { kRed, kGreen, kBlue };

struct Record {
  int count = 0;
  bool open = false;
  double weight = 0.0;
  Colour colour = Colour::kRed;
  std::string name;
  std::vector<int> ids;
  std::vector<double> values;
  std::vector<Colour> history;
};

// The layout of a Record, for a writer (Self = const Record) or a reader.
template <class Stream, class Self>
void Transfer(Stream* io, Self* r) {
  io->Field(&r->count, "the count");
  io->Field(&r->open, "whether it is open");
  io->Field(&r->weight, "the weight");
  io->Field(&r->colour, "the colour", Colour::kBlue);
  io->Field(&r->name, "the name");
  io->Field(&r->ids, "the ids");
  io->Field(&r->values, "the values");
  io->Size(&r->history, sizeof(std::int64_t), "the history");
  for (auto& c : r->history) io->Field(&c, "a past colour", Colour::kBlue);
}

std::string Written(const Record& r) {
  ByteWriter out;
  Transfer(&out, &r);
  return out.bytes();
}

TEST(ByteStream, AStateDescribedOnceReadsBackAsWritten) {
  Record r;
  r.count = -7;
  r.open = true;
  r.weight = 0.1;
  r.colour = Colour::kGreen;
  r.name = "map";
  r.ids = {3, 1, 4};
  r.values = {2.5, -1e-300};
  r.history = {Colour::kBlue, Colour::kRed};
  const std::string bytes = Written(r);
  Record back;
  ByteReader in(bytes);
  Transfer(&in, &back);
  EXPECT_TRUE(in.AtEnd());
  EXPECT_EQ(back.count, -7);
  EXPECT_TRUE(back.open);
  EXPECT_EQ(back.weight, 0.1);
  EXPECT_EQ(back.colour, Colour::kGreen);
  EXPECT_EQ(back.name, "map");
  EXPECT_EQ(back.ids, r.ids);
  EXPECT_EQ(back.values, r.values);
  EXPECT_EQ(back.history, r.history);
  EXPECT_EQ(Written(back), bytes);
}

TEST(ByteStream, AnEnumOutOfItsRangeIsRefusedNamingIt) {
  ByteWriter out;
  const int three = 3;
  out.Field(&three, "a colour that does not exist");
  ByteReader in(out.bytes());
  Colour c = Colour::kRed;
  try {
    in.Field(&c, "the colour", Colour::kBlue);
    FAIL() << "read an unknown colour";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "the colour has the unknown value 3");
  }
}

TEST(ByteStream, ASizeTheBytesCannotHoldIsRefusedNamingIt) {
  Record r;
  r.history = {Colour::kRed, Colour::kGreen};
  std::string bytes = Written(r);
  bytes.resize(bytes.size() - sizeof(std::int64_t));
  Record back;
  ByteReader in(bytes);
  try {
    Transfer(&in, &back);
    FAIL() << "read a history longer than its bytes";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()),
              "the history: count 2 does not fit the state");
  }
}

}  // namespace
}  // namespace rrr
