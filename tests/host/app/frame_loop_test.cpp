#include "app/daemon/frame_loop.h"

#include <gtest/gtest.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include "hal/fake/fake_camera.h"
#include "tests/host/support/test_data.h"

#include <fstream>
#include <sstream>

namespace ale::app {
namespace {

// A lens for the fake camera's frames (the pipeline needs one; the tests here exercise the loop).
hal::CameraCalibration test_lens() {
  hal::CameraCalibration c;
  c.fx = c.fy = 50.0;
  c.cx = 32.0;
  c.cy = 24.0;
  return c;
}

LoopDeps deps_of(hal::Camera& cam, hal::PoseSink& sink, hal::Gpio& gpio, int stop_fd = -1) {
  LoopDeps d{cam, sink, gpio, stop_fd};
  d.calibration = test_lens();
  return d;
}

std::vector<GrayImage> frames(int n) {
  std::vector<GrayImage> v;
  for (int i = 0; i < n; ++i) v.emplace_back(64, 48, static_cast<std::uint8_t>(10 * i));
  return v;
}

TEST(FrameLoopTest, PublishesPoseAndStatusForEveryFrameUntilTheEnd) {
  hal::FakeCamera cam(frames(5));
  hal::FakePoseSink sink;
  hal::FakeGpio gpio;
  DaemonConfig config;
  RunSummary summary;
  Status s = run_frame_loop(config, deps_of(cam, sink, gpio), summary);
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

TEST(FrameLoopTest, GradesEveryFrameAndWritesTheFrameLog) {
  std::vector<GrayImage> v;
  v.emplace_back(64, 48, 20);   // extremely dark
  v.emplace_back(64, 48, 128);  // normal
  hal::FakeCamera::Options o;
  o.period_ns = 50000000;
  hal::FakeCamera cam(std::move(v), o);
  hal::FakePoseSink sink;
  hal::NullGpio gpio;
  DaemonConfig config;
  config.features.enhance.grading.hysteresis = 0;
  config.daemon.frame_log = test::make_temp_dir("frame-log") + "/frames.csv";
  RunSummary summary;
  Status s = run_frame_loop(config, deps_of(cam, sink, gpio), summary);
  ASSERT_TRUE(s.ok()) << s.to_string();
  ASSERT_EQ(sink.reports.size(), 2u);
  EXPECT_EQ(sink.reports[0].brightness, BrightnessClass::kExtremelyDark);
  EXPECT_EQ(sink.reports[1].brightness, BrightnessClass::kNormal);
  std::ifstream in(config.daemon.frame_log);
  std::stringstream text;
  text << in.rdbuf();
  const std::string csv = text.str();
  EXPECT_EQ(csv.rfind("#timestamp_ns,sequence,state,brightness,", 0), 0u) << csv;
  EXPECT_NE(csv.find("\n0,0,not_initialized,extremely_dark,20.00,"), std::string::npos) << csv;
  EXPECT_NE(csv.find("\n50000000,1,not_initialized,normal,128.00,"), std::string::npos) << csv;
}

TEST(FrameLoopTest, ReportsTheFeaturesOfTheOrbFrontEnd) {
  GrayImage board(160, 120);
  for (int y = 0; y < board.height; ++y)
    for (int x = 0; x < board.width; ++x)
      board.view().at(x, y) = static_cast<std::uint8_t>(((x / 10 + y / 10) % 2) ? 200 : 40);
  std::vector<GrayImage> v;
  v.push_back(board);
  v.emplace_back(160, 120, 128);  // flat: nothing to detect
  hal::FakeCamera cam(std::move(v));
  hal::FakePoseSink sink;
  hal::NullGpio gpio;
  DaemonConfig config;
  RunSummary summary;
  ASSERT_TRUE(run_frame_loop(config, deps_of(cam, sink, gpio), summary).ok());
  ASSERT_EQ(sink.reports.size(), 2u);
  EXPECT_GT(sink.reports[0].features, 20);
  EXPECT_LE(sink.reports[0].features, config.features.num_features);
  EXPECT_EQ(sink.reports[1].features, 0);
}

TEST(FrameLoopTest, UnwritableFrameLogStopsBeforeTheCameraStarts) {
  hal::FakeCamera cam(frames(2));
  hal::FakePoseSink sink;
  hal::NullGpio gpio;
  DaemonConfig config;
  config.daemon.frame_log = "/nonexistent-dir/frames.csv";
  RunSummary summary;
  Status s = run_frame_loop(config, deps_of(cam, sink, gpio), summary);
  EXPECT_EQ(s.code(), StatusCode::kIoError);
  EXPECT_NE(s.message().find("/nonexistent-dir/frames.csv"), std::string::npos);
  EXPECT_TRUE(sink.poses.empty());
}

TEST(FrameLoopTest, StopsAtMaxFrames) {
  hal::FakeCamera cam(frames(5));
  hal::FakePoseSink sink;
  hal::NullGpio gpio;
  DaemonConfig config;
  config.daemon.max_frames = 2;
  RunSummary summary;
  ASSERT_TRUE(run_frame_loop(config, deps_of(cam, sink, gpio), summary).ok());
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
  Status s = run_frame_loop(config, deps_of(cam, sink, gpio), summary);
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
  ASSERT_TRUE(run_frame_loop(config, deps_of(cam, sink, gpio, fd), summary).ok());
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
  Status s = run_frame_loop(config, deps_of(cam, sink, gpio), summary);
  ::close(pipe_fds[0]);
  ::close(pipe_fds[1]);
  EXPECT_EQ(s.code(), StatusCode::kTimeout);
  EXPECT_NE(s.message().find("fake camera"), std::string::npos) << s.message();
  EXPECT_EQ(summary.frame_errors, 3u);
  EXPECT_EQ(summary.frames, 0u);
}

}  // namespace
}  // namespace ale::app
