#include "rrr/io/text_fields.h"

#include <gtest/gtest.h>

#include <string>

#include "rrr/io/input_error.h"

namespace rrr {
namespace {

TEST(TextFields, SplitsAtAnyRunOfWhiteSpace) {
  const TextFields f("  EDGE_SE2\t0  1 \t0.5\r\n", "a.g2o", 3);
  ASSERT_EQ(f.size(), 4u);
  EXPECT_EQ(f[0], "EDGE_SE2");
  EXPECT_EQ(f.Integer(1), 0);
  EXPECT_EQ(f.Integer(2), 1);
  EXPECT_EQ(f.Number(3), 0.5);
  EXPECT_TRUE(TextFields(" \t ", "a.g2o", 4).IsComment());
  EXPECT_TRUE(TextFields("# VERTEX_SE2 0 0 0 0", "a.g2o", 5).IsComment());
}

TEST(TextFields, CommasSeparateOnlyWhenAsked) {
  const TextFields csv("1.5,2,,-3e2", "truth.csv", 1, true);
  ASSERT_EQ(csv.size(), 3u);
  EXPECT_EQ(csv.Numbers(0), (std::vector<double>{1.5, 2.0, -300.0}));
  const TextFields text("1.5,2", "truth.txt", 1);
  ASSERT_EQ(text.size(), 1u);
  EXPECT_THROW(text.Number(0), InputError);
}

TEST(TextFields, ReadsNumbersAsStrtodReadsDecimalOnes) {
  const TextFields f("+1.5 +7 -2.5e-3 .25 +-1 1.5x 0x10 + 1e400", "g", 1);
  EXPECT_EQ(f.Number(0), 1.5);
  EXPECT_EQ(f.Integer(1), 7);
  EXPECT_EQ(f.Number(2), -2.5e-3);
  EXPECT_EQ(f.Number(3), 0.25);
  for (size_t k = 4; k < f.size(); ++k) {
    EXPECT_THROW(f.Number(k), InputError) << f[k];
  }
  EXPECT_THROW(f.Integer(0), InputError);
  // The nearest double, as strtod rounds.
  EXPECT_EQ(TextFields("0.1 2.2250738585072014e-308", "g", 1).Numbers(0),
            (std::vector<double>{0.1, 2.2250738585072014e-308}));
}

TEST(TextFields, ABadNumberNamesTheFileLineAndField) {
  const TextFields f("VERTEX_SE2 0 1.0 x 3", "graph.g2o", 12);
  try {
    f.Numbers(2);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "graph.g2o:12: field 3 'x' is not a number");
  }
  EXPECT_THROW(TextFields("VERTEX_SE2 0 1e999", "g", 1).Number(2), InputError);
}

}  // namespace
}  // namespace rrr
