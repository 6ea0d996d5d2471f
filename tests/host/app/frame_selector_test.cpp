#include "app/daemon/frame_selector.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace ale::app {
namespace {

// '1' processed, '0' skipped, for frames at `fps` (with +-jitter_ns alternating).
std::string pattern(FrameSelector& s, double fps, int n, std::int64_t jitter_ns = 0, std::int64_t t0 = 5000000000LL) {
  std::string out;
  for (int i = 0; i < n; ++i) {
    const std::int64_t t = t0 + static_cast<std::int64_t>(std::llround(i * 1e9 / fps)) + (i % 2 ? jitter_ns : -jitter_ns);
    out += s.take(t) ? '1' : '0';
  }
  return out;
}

TEST(FrameSelectorTest, ZeroTakesEveryFrame) {
  FrameSelector s(0);
  EXPECT_EQ(pattern(s, 30, 6), "111111");
}

TEST(FrameSelectorTest, HalfTheSensorRateTakesEveryOtherFrame) {
  FrameSelector s(15);
  EXPECT_EQ(pattern(s, 30, 10), "1010101010");
}

TEST(FrameSelectorTest, TwoThirdsAreEvenlySpaced) {
  FrameSelector s(20);
  const std::string p = pattern(s, 30, 30);
  EXPECT_EQ(p, "101101101101101101101101101101");  // frames at 0, 67, 100, 167, 200... ms
}

TEST(FrameSelectorTest, JitterDoesNotChangeTheChoice) {
  FrameSelector s(15);
  EXPECT_EQ(pattern(s, 30, 10, 3000000), "1010101010");  // +-3 ms on 33 ms frames
}

TEST(FrameSelectorTest, AFasterTargetThanTheSensorTakesEverything) {
  FrameSelector s(60);
  EXPECT_EQ(pattern(s, 30, 6), "111111");
}

TEST(FrameSelectorTest, AGapRestartsTheGrid) {
  FrameSelector s(15);
  EXPECT_TRUE(s.take(0));
  EXPECT_FALSE(s.take(33333333));
  EXPECT_TRUE(s.take(1000000000));  // a second of nothing: taken, the grid starts again here
  EXPECT_FALSE(s.take(1033333333));
  EXPECT_TRUE(s.take(1066666667));
}

}  // namespace
}  // namespace ale::app
