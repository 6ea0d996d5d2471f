#include "core/base/memory_pool.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <set>
#include <vector>

namespace ale {
namespace {

TEST(BlockPoolTest, BlocksAreDistinctAlignedAndWritable) {
  BlockPool pool("test", 100, 8);
  EXPECT_EQ(pool.block_bytes() % BlockPool::kAlignment, 0u);
  EXPECT_GE(pool.block_bytes(), 100u);
  std::set<void*> seen;
  for (int i = 0; i < 8; ++i) {
    Result<void*> b = pool.allocate();
    ASSERT_TRUE(b.ok()) << b.status().to_string();
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(*b) % BlockPool::kAlignment, 0u);
    std::memset(*b, i, 100);
    EXPECT_TRUE(seen.insert(*b).second);
  }
  EXPECT_EQ(pool.stats().in_use, 8u);
}

TEST(BlockPoolTest, ExhaustionIsAnErrorAndCounted) {
  BlockPool pool("frames", 64, 2);
  Result<void*> a = pool.allocate();
  Result<void*> b = pool.allocate();
  ASSERT_TRUE(a.ok());
  ASSERT_TRUE(b.ok());
  Result<void*> c = pool.allocate();
  ASSERT_FALSE(c.ok());
  EXPECT_EQ(c.status().code(), StatusCode::kOutOfMemory);
  EXPECT_NE(c.status().message().find("frames"), std::string::npos);
  EXPECT_EQ(pool.stats().failures, 1u);
  ASSERT_TRUE(pool.free(*a).ok());
  Result<void*> d = pool.allocate();
  ASSERT_TRUE(d.ok());
  EXPECT_EQ(*d, *a);  // the freed block is reused
}

TEST(BlockPoolTest, HighWaterMarkTracksPeakUse) {
  BlockPool pool("hw", 32, 4);
  std::vector<void*> held;
  for (int i = 0; i < 3; ++i) held.push_back(*pool.allocate());
  for (void* p : held) ASSERT_TRUE(pool.free(p).ok());
  ASSERT_TRUE(pool.allocate().ok());
  EXPECT_EQ(pool.stats().high_water, 3u);
  EXPECT_EQ(pool.stats().in_use, 1u);
  EXPECT_EQ(pool.stats().allocations, 4u);
}

TEST(BlockPoolTest, RejectsForeignAndDoubleFrees) {
  BlockPool pool("p", 64, 2);
  void* a = *pool.allocate();
  int on_stack = 0;
  EXPECT_EQ(pool.free(&on_stack).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(pool.free(static_cast<std::uint8_t*>(a) + 1).code(), StatusCode::kInvalidArgument);
  ASSERT_TRUE(pool.free(a).ok());
  EXPECT_EQ(pool.free(a).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(pool.stats().bad_frees, 3u);
  EXPECT_EQ(pool.stats().in_use, 0u);
}

TEST(BlockPoolTest, EmptyPoolRefusesEverything) {
  BlockPool pool("empty", 0, 0);
  EXPECT_EQ(pool.allocate().status().code(), StatusCode::kOutOfMemory);
}

}  // namespace
}  // namespace ale
