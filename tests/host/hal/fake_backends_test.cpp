#include <gtest/gtest.h>

#include "hal/clock.h"
#include "hal/fake/fake_camera.h"
#include "hal/gpio.h"
#include "hal/pose_sink.h"

namespace ale::hal {
namespace {

std::vector<GrayImage> frames(int n) {
  std::vector<GrayImage> v;
  for (int i = 0; i < n; ++i) v.emplace_back(8, 4, static_cast<std::uint8_t>(i));
  return v;
}

TEST(FakeCameraTest, LendsFramesInOrderThenEndsTheStream) {
  FakeCamera cam(frames(3));
  ASSERT_TRUE(cam.start().ok());
  for (int i = 0; i < 3; ++i) {
    Frame f;
    ASSERT_TRUE(cam.acquire(f, 0).ok());
    EXPECT_EQ(f.sequence, static_cast<std::uint64_t>(i));
    EXPECT_EQ(f.image.at(3, 2), i);
    EXPECT_EQ(f.timestamp_ns, i * 33333333LL);
    ASSERT_TRUE(cam.release(f).ok());
  }
  Frame f;
  EXPECT_EQ(cam.acquire(f, 0).code(), StatusCode::kEndOfStream);
}

TEST(FakeCameraTest, AllBuffersLentIsOutOfMemoryUntilOneIsReleased) {
  FakeCamera::Options o;
  o.buffers = 2;
  FakeCamera cam(frames(4), o);
  ASSERT_TRUE(cam.start().ok());
  Frame a, b, c;
  ASSERT_TRUE(cam.acquire(a, 0).ok());
  ASSERT_TRUE(cam.acquire(b, 0).ok());
  EXPECT_EQ(cam.acquire(c, 0).code(), StatusCode::kOutOfMemory);
  ASSERT_TRUE(cam.release(a).ok());
  EXPECT_EQ(cam.release(a).code(), StatusCode::kInvalidArgument);
  ASSERT_TRUE(cam.acquire(c, 0).ok());
  EXPECT_EQ(c.sequence, 2u);
}

TEST(FakeCameraTest, VanishingCameraIsUnavailable) {
  FakeCamera::Options o;
  o.vanish_after = 1;
  FakeCamera cam(frames(3), o);
  ASSERT_TRUE(cam.start().ok());
  Frame f;
  ASSERT_TRUE(cam.acquire(f, 0).ok());
  ASSERT_TRUE(cam.release(f).ok());
  EXPECT_EQ(cam.acquire(f, 0).code(), StatusCode::kUnavailable);
  EXPECT_EQ(cam.stats().errors, 1u);
}

TEST(ManualClockTest, NeverGoesBackwards) {
  ManualClock clock(100);
  EXPECT_TRUE(clock.set_ns(200));
  EXPECT_FALSE(clock.set_ns(150));
  EXPECT_EQ(clock.now_ns(), 200);
  clock.advance_ns(-5);
  EXPECT_EQ(clock.now_ns(), 200);
}

TEST(FakeBackendsTest, GpioAndPoseSinkRecord) {
  FakeGpio gpio;
  ASSERT_TRUE(gpio.set(GpioLine::kIrIlluminator, true).ok());
  EXPECT_TRUE(gpio.state(GpioLine::kIrIlluminator));
  EXPECT_FALSE(gpio.state(GpioLine::kStatusLed));
  FakePoseSink sink;
  PoseEstimate p;
  p.timestamp_ns = 5;
  ASSERT_TRUE(sink.publish(p).ok());
  ASSERT_EQ(sink.poses.size(), 1u);
  EXPECT_EQ(sink.poses[0].timestamp_ns, 5);
  EXPECT_STREQ(to_string(GpioLine::kStatusLed), "status_led");
}

}  // namespace
}  // namespace ale::hal
