#include "app/daemon/frame_loop.h"

#include <gtest/gtest.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include "hal/fake/fake_camera.h"

namespace ale::app {
namespace {

std::vector<GrayImage> frames(int n) {
  std::vector<GrayImage> v;
  for (int i = 0; i < n; ++i) v.emplace_back(16, 8, static_cast<std::uint8_t>(10 * i));
  return v;
}

TEST(FrameLoopTest, PublishesPoseAndStatusForEveryFrameUntilTheEnd) {
  hal::FakeCamera cam(frames(5));
  hal::FakePoseSink sink;
  hal::FakeGpio gpio;
  DaemonConfig config;
  RunSummary summary;
  Status s = run_frame_loop(config, LoopDeps{cam, sink, gpio}, summary);
  ASSERT_TRUE(s.ok()) << s.to_string();
  EXPECT_TRUE(summary.end_of_stream);
  EXPECT_EQ(summary.frames, 5u);
  ASSERT_EQ(sink.poses.size(), 5u);
  ASSERT_EQ(sink.reports.size(), 5u);
  EXPECT_EQ(sink.poses[3].frame_sequence, 3u);
  EXPECT_FLOAT_EQ(sink.reports[2].mean_intensity, 20.0f);
  EXPECT_EQ(cam.pool().stats().in_use, 0u) << "every frame must be released";
  EXPECT_FALSE(gpio.state(hal::GpioLine::kStatusLed)) << "LED off after the loop";
}

TEST(FrameLoopTest, StopsAtMaxFrames) {
  hal::FakeCamera cam(frames(5));
  hal::FakePoseSink sink;
  hal::NullGpio gpio;
  DaemonConfig config;
  config.max_frames = 2;
  RunSummary summary;
  ASSERT_TRUE(run_frame_loop(config, LoopDeps{cam, sink, gpio}, summary).ok());
  EXPECT_EQ(summary.frames, 2u);
  EXPECT_FALSE(summary.end_of_stream);
}

TEST(FrameLoopTest, VanishingCameraEndsTheLoopWithItsReason) {
  hal::FakeCamera::Options o;
  o.vanish_after = 3;
  hal::FakeCamera cam(frames(5), o);
  hal::FakePoseSink sink;
  hal::NullGpio gpio;
  DaemonConfig config;
  RunSummary summary;
  Status s = run_frame_loop(config, LoopDeps{cam, sink, gpio}, summary);
  EXPECT_EQ(s.code(), StatusCode::kUnavailable);
  EXPECT_EQ(summary.frames, 3u);
  EXPECT_EQ(sink.poses.size(), 3u) << "frames before the failure are not lost";
}

TEST(FrameLoopTest, StopRequestEndsTheLoopCleanly) {
  hal::FakeCamera cam(frames(5));
  hal::FakePoseSink sink;
  hal::NullGpio gpio;
  DaemonConfig config;
  const int fd = eventfd(1, EFD_NONBLOCK);  // already readable: a signal arrived
  ASSERT_GE(fd, 0);
  RunSummary summary;
  ASSERT_TRUE(run_frame_loop(config, LoopDeps{cam, sink, gpio, fd}, summary).ok());
  ::close(fd);
  EXPECT_TRUE(summary.stopped_by_signal);
  EXPECT_EQ(summary.frames, 0u);
}

TEST(FrameLoopTest, SilentCameraTimesOutAndStopsAfterTheConfiguredErrors) {
  int pipe_fds[2];
  ASSERT_EQ(::pipe(pipe_fds), 0);  // never written: the camera never becomes readable
  hal::FakeCamera::Options o;
  o.poll_fd = pipe_fds[0];
  hal::FakeCamera cam(frames(5), o);
  hal::FakePoseSink sink;
  hal::NullGpio gpio;
  DaemonConfig config;
  config.camera.acquire_timeout_ms = 10;
  config.camera.max_consecutive_errors = 3;
  RunSummary summary;
  Status s = run_frame_loop(config, LoopDeps{cam, sink, gpio}, summary);
  ::close(pipe_fds[0]);
  ::close(pipe_fds[1]);
  EXPECT_EQ(s.code(), StatusCode::kTimeout);
  EXPECT_NE(s.message().find("fake camera"), std::string::npos) << s.message();
  EXPECT_EQ(summary.frame_errors, 3u);
  EXPECT_EQ(summary.frames, 0u);
}

}  // namespace
}  // namespace ale::app
