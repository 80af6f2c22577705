#include "rrr/solver/process_memory.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace rrr {
namespace {

#if defined(__GLIBC__)
TEST(KeepFreedMemory, BlocksUpToTheLimitComeFromTheArenaAndStayAfterFree) {
  ASSERT_TRUE(KeepFreedMemory());
  // Over glibc's largest default threshold (32 MB), under the limit.
  constexpr size_t kBlock = 64 << 20;
  const struct mallinfo2 before = mallinfo2();
  char* block = static_cast<char*>(std::malloc(kBlock));
  ASSERT_NE(block, nullptr);
  std::memset(block, 1, kBlock);
  // Not a mapping of its own.
  EXPECT_EQ(mallinfo2().hblkhd, before.hblkhd);
  std::free(block);
  // Freed, it stays in the process for the next solve.
  EXPECT_GE(mallinfo2().fordblks, kBlock);
}
#endif

}  // namespace
}  // namespace rrr
