#include "hal/linux/monotonic_clock.h"

#include <gtest/gtest.h>
#include <time.h>

#include <cstdint>

namespace ale::linux_hal {
namespace {

TEST(MonotonicClock, NeverGoesBackwards) {
  MonotonicClock clock;
  std::int64_t last = clock.now_ns();
  EXPECT_GT(last, 0);
  for (int i = 0; i < 100000; ++i) {
    const std::int64_t now = clock.now_ns();
    ASSERT_GE(now, last) << "after " << i << " reads";
    last = now;
  }
}

TEST(MonotonicClock, FollowsASleep) {
  MonotonicClock clock;
  const std::int64_t before = clock.now_ns();
  const timespec five_ms{0, 5000000};
  nanosleep(&five_ms, nullptr);
  const std::int64_t slept = clock.now_ns() - before;
  EXPECT_GE(slept, 5000000);
  EXPECT_LT(slept, 5000000000);  // even a loaded qemu does not take 5 s for this
}

}  // namespace
}  // namespace ale::linux_hal
