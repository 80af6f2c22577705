#include "input_queue.h"

#include <gtest/gtest.h>

#include <thread>

namespace rrr_ros {
namespace {

TEST(InputQueue, RefusesOnlyRefusableInputsBeyondItsCapacity) {
  InputQueue<int> queue(2);
  EXPECT_TRUE(queue.Push(1, true));
  EXPECT_TRUE(queue.Push(2, true));
  EXPECT_FALSE(queue.Push(3, true));
  EXPECT_TRUE(queue.Push(4, false));  // a request always gets in
  EXPECT_EQ(queue.size(), 3u);
  EXPECT_EQ(queue.refused(), 1u);
  const auto batch = queue.TakeAll();
  ASSERT_EQ(batch.size(), 3u);
  EXPECT_EQ(batch[0].input, 1);
  EXPECT_EQ(batch[1].input, 2);
  EXPECT_EQ(batch[2].input, 4);
  EXPECT_LE(batch[0].time, batch[2].time);
  EXPECT_EQ(queue.size(), 0u);
  EXPECT_EQ(queue.longest(), 3u);
  EXPECT_TRUE(queue.Push(5, true));  // room again once taken
}

TEST(InputQueue, HandsEveryInputOverBeforeStopping) {
  InputQueue<int> queue(1000);
  std::thread producer([&] {
    for (int k = 0; k < 500; ++k) queue.Push(k, true);
    queue.Stop();
  });
  int expected = 0;
  for (auto batch = queue.TakeAll(); !batch.empty(); batch = queue.TakeAll()) {
    for (const auto& arrival : batch) EXPECT_EQ(arrival.input, expected++);
  }
  producer.join();
  EXPECT_EQ(expected, 500);
  EXPECT_EQ(queue.refused(), 0u);
}

}  // namespace
}  // namespace rrr_ros
