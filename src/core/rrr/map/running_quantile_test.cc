#include "rrr/rrr/map/running_quantile.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

namespace rrr {
namespace {

// The value at index ⌊q·(n − 1)⌋ of `values` sorted.
double SortedQuantile(std::vector<double> values, double q) {
  std::sort(values.begin(), values.end());
  return values[static_cast<size_t>(q *
                                    static_cast<double>(values.size() - 1))];
}

TEST(RunningQuantile, EqualsTheSortedSamplesQuantileAfterEveryValue) {
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> coarse(0, 20);  // many ties
  std::lognormal_distribution<double> spread(0.0, 2.0);
  for (const double q : {0.0, 0.05, 0.5, 0.9, 1.0}) {
    RunningQuantile running(q);
    std::vector<double> seen;
    for (int k = 0; k < 500; ++k) {
      const double v = k % 3 == 0 ? coarse(rng) : spread(rng);
      running.Add(v);
      seen.push_back(v);
      ASSERT_EQ(running.size(), static_cast<int>(seen.size()));
      ASSERT_EQ(running.Value(), SortedQuantile(seen, q))
          << "q " << q << " after " << seen.size() << " values";
    }
  }
}

TEST(RunningQuantile, ValuesInAnyOrderGiveTheSameQuantile) {
  std::vector<double> values(101);
  for (int k = 0; k <= 100; ++k) values[k] = k;
  RunningQuantile rising(0.05), falling(0.05);
  for (const double v : values) rising.Add(v);
  for (auto it = values.rbegin(); it != values.rend(); ++it) falling.Add(*it);
  EXPECT_EQ(rising.Value(), 5.0);
  EXPECT_EQ(falling.Value(), 5.0);
}

TEST(RunningQuantile, StaysTheSortedSamplesQuantileAsValuesLeave) {
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> coarse(0, 10);  // many ties
  for (const double q : {0.0, 0.5, 1.0}) {
    RunningQuantile running(q);
    std::vector<double> kept;
    for (int k = 0; k < 600; ++k) {
      // Mostly adds, sometimes removes a value kept (or one never added).
      if (k % 3 == 2 && !kept.empty()) {
        const size_t at = rng() % kept.size();
        ASSERT_TRUE(running.Remove(kept[at]));
        kept.erase(kept.begin() + static_cast<std::ptrdiff_t>(at));
      } else {
        const double v = coarse(rng);
        running.Add(v);
        kept.push_back(v);
      }
      EXPECT_FALSE(running.Remove(-1.0));
      ASSERT_EQ(running.size(), static_cast<int>(kept.size()));
      if (!kept.empty()) {
        ASSERT_EQ(running.Value(), SortedQuantile(kept, q)) << "q " << q;
      }
    }
  }
}

}  // namespace
}  // namespace rrr
