#include "rrr/graph/stamped_candidates.h"

#include <gtest/gtest.h>

#include <string>
#include <tuple>

namespace rrr {
namespace {

// Keyframes at 0, 100, 200 ns, matched within 10 ns.
KeyframeStamps ThreeKeyframes() {
  KeyframeStamps stamps(10);
  for (const std::int64_t t : {0, 100, 200}) stamps.Append(t);
  return stamps;
}

struct Outcomes {
  std::vector<std::tuple<int, int, std::string>> found;
  std::vector<std::pair<std::string, std::string>> missing;
};

Outcomes ResolveAll(StampedCandidates<std::string>* held,
                    const KeyframeStamps& stamps) {
  Outcomes out;
  held->Resolve(
      stamps,
      [&](int from, int to, const std::string& c) {
        out.found.emplace_back(from, to, c);
      },
      [&](const char* end, const std::string& c) {
        out.missing.emplace_back(end, c);
      });
  return out;
}

TEST(StampedCandidates, HandsOverWhatTheKeyframesResolveAndKeepsTheRest) {
  StampedCandidates<std::string> held(10);
  ASSERT_TRUE(held.Hold(103, 3, "a"));    // both near keyframes
  ASSERT_TRUE(held.Hold(350, 100, "b"));  // after the newest: not yet
  ASSERT_TRUE(held.Hold(205, 100, "e"));  // within 10 ns of it, but later
  ASSERT_TRUE(held.Hold(150, 0, "c"));    // between keyframes: none
  ASSERT_TRUE(held.Hold(0, 50, "d"));     // its `to` has none
  const Outcomes first = ResolveAll(&held, ThreeKeyframes());
  EXPECT_EQ(first.found,
            (std::vector<std::tuple<int, int, std::string>>{{1, 0, "a"}}));
  EXPECT_EQ(first.missing, (std::vector<std::pair<std::string, std::string>>{
                               {"from", "c"}, {"to", "d"}}));
  EXPECT_EQ(held.size(), 2);
  KeyframeStamps later = ThreeKeyframes();
  later.Append(352);
  const Outcomes second = ResolveAll(&held, later);
  EXPECT_EQ(second.found, (std::vector<std::tuple<int, int, std::string>>{
                              {3, 1, "b"}, {2, 1, "e"}}));
  EXPECT_EQ(held.size(), 0);
}

TEST(StampedCandidates, RefusesBeyondItsCapacity) {
  StampedCandidates<std::string> held(2);
  EXPECT_TRUE(held.Hold(500, 0, "a"));
  EXPECT_TRUE(held.Hold(600, 0, "b"));
  EXPECT_FALSE(held.Hold(700, 0, "c"));
  EXPECT_EQ(held.size(), 2);
  ResolveAll(&held, ThreeKeyframes());  // all still wait
  EXPECT_FALSE(held.Hold(700, 0, "c"));
}

}  // namespace
}  // namespace rrr
