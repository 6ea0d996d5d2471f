#include "hal/linux/v4l2_camera.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <memory>
#include <string>

#include "hal/linux/monotonic_clock.h"
#include "tests/host/hal/linux/fake_v4l2_driver.h"
#include "tests/host/support/test_data.h"

namespace ale::linux_hal {
namespace {

using test::FakeV4l2Driver;

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// --- real devices (no camera needed) ---

TEST(V4l2CameraDevice, NonexistentDeviceIsNotFoundAndNamed) {
  V4l2CameraOptions o;
  o.device = "/dev/video97";
  auto camera = V4l2Camera::open(o);
  ASSERT_FALSE(camera.ok());
  EXPECT_EQ(camera.status().code(), StatusCode::kNotFound) << camera.status().to_string();
  EXPECT_TRUE(contains(camera.status().message(), "/dev/video97")) << camera.status().message();
}

TEST(V4l2CameraDevice, RegularFileIsNotAV4l2Device) {
  const std::string dir = test::make_temp_dir("v4l2_camera");
  const std::string path = dir + "/not_a_camera";
  ASSERT_TRUE(test::write_file(path, "hello"));
  V4l2CameraOptions o;
  o.device = path;
  auto camera = V4l2Camera::open(o);
  ASSERT_FALSE(camera.ok());
  EXPECT_EQ(camera.status().code(), StatusCode::kInvalidArgument) << camera.status().to_string();
  EXPECT_TRUE(contains(camera.status().message(), path)) << camera.status().message();
  EXPECT_TRUE(contains(camera.status().message(), "not a V4L2 device")) << camera.status().message();
}

TEST(V4l2CameraDevice, DevNullIsNotAV4l2Device) {
  V4l2CameraOptions o;
  o.device = "/dev/null";
  auto camera = V4l2Camera::open(o);
  ASSERT_FALSE(camera.ok());
  EXPECT_EQ(camera.status().code(), StatusCode::kInvalidArgument) << camera.status().to_string();
  EXPECT_TRUE(contains(camera.status().message(), "/dev/null is not a V4L2 device")) << camera.status().message();
  EXPECT_TRUE(contains(camera.status().message(), "character device 1:3")) << camera.status().message();
}

TEST(V4l2CameraDevice, BadOptionsAreRejectedBeforeOpening) {
  V4l2CameraOptions o;
  o.device = "/dev/null";
  o.buffers = 1;
  auto camera = V4l2Camera::open(o);
  ASSERT_FALSE(camera.ok());
  EXPECT_EQ(camera.status().code(), StatusCode::kInvalidArgument);
  EXPECT_TRUE(contains(camera.status().message(), "buffers 1")) << camera.status().message();
}

// --- a driver in memory ---

class V4l2CameraFake : public ::testing::Test {
 protected:
  V4l2CameraOptions options() const {
    V4l2CameraOptions o;
    o.device = driver_.path;
    o.width = 64;
    o.height = 48;
    o.buffers = 3;
    return o;
  }
  std::unique_ptr<V4l2Camera> open_ok(const V4l2CameraOptions& o) {
    auto camera = V4l2Camera::open(o, driver_);
    EXPECT_TRUE(camera.ok()) << camera.status().to_string();
    return camera.ok() ? std::move(camera.value()) : nullptr;
  }
  std::unique_ptr<V4l2Camera> start_ok() {
    auto camera = open_ok(options());
    if (camera) {
      Status s = camera->start();
      EXPECT_TRUE(s.ok()) << s.to_string();
    }
    return camera;
  }
  void add_shots(int n, std::uint32_t first_sequence = 0) {
    for (int i = 0; i < n; ++i) {
      const auto k = static_cast<std::uint32_t>(i);
      driver_.shots.push_back({first_sequence + k, 1000000000 + 33000000 * static_cast<std::int64_t>(k),
                               static_cast<std::uint8_t>(10 * k), false, ~0u, nullptr});
    }
  }
  // Every pixel of the frame against the pattern the driver painted.
  static int mismatches(const hal::Frame& f, std::uint8_t seed) {
    int bad = 0;
    for (int y = 0; y < f.image.height; ++y)
      for (int x = 0; x < f.image.width; ++x) bad += f.image.at(x, y) != FakeV4l2Driver::pattern(x, y, seed);
    return bad;
  }

  FakeV4l2Driver driver_;
};

TEST_F(V4l2CameraFake, PrefersGreyThenPlanarThenPacked) {
  driver_.formats = {V4L2_PIX_FMT_YUYV, V4L2_PIX_FMT_NV12, V4L2_PIX_FMT_GREY};
  auto camera = open_ok(options());
  ASSERT_NE(camera, nullptr);
  EXPECT_EQ(camera->format().fourcc, V4L2_PIX_FMT_GREY);
  camera.reset();
  driver_.formats = {V4L2_PIX_FMT_YUYV, V4L2_PIX_FMT_NV12};
  camera = open_ok(options());
  ASSERT_NE(camera, nullptr);
  EXPECT_EQ(camera->format().fourcc, V4L2_PIX_FMT_NV12);
  EXPECT_TRUE(contains(camera->describe(), "NV12 (Y plane taken as grey")) << camera->describe();
}

TEST_F(V4l2CameraFake, NoLumaFormatIsUnsupportedAndListsWhatIsOffered) {
  driver_.formats = {V4L2_PIX_FMT_MJPEG};
  auto camera = V4l2Camera::open(options(), driver_);
  ASSERT_FALSE(camera.ok());
  EXPECT_EQ(camera.status().code(), StatusCode::kUnsupported);
  EXPECT_TRUE(contains(camera.status().message(), "MJPG")) << camera.status().message();
  EXPECT_EQ(driver_.open_fds, 0);  // closed again
}

TEST_F(V4l2CameraFake, WrongSizeIsUnsupportedAndSaysWhatTheDriverGave) {
  driver_.max_width = 32;
  driver_.max_height = 24;
  auto camera = V4l2Camera::open(options(), driver_);
  ASSERT_FALSE(camera.ok());
  EXPECT_EQ(camera.status().code(), StatusCode::kUnsupported);
  EXPECT_TRUE(contains(camera.status().message(), "64x48")) << camera.status().message();
  EXPECT_TRUE(contains(camera.status().message(), "32x24")) << camera.status().message();
}

TEST_F(V4l2CameraFake, NotCaptureOrNotStreamingIsUnsupported) {
  driver_.caps = V4L2_CAP_VIDEO_OUTPUT | V4L2_CAP_STREAMING;
  auto camera = V4l2Camera::open(options(), driver_);
  ASSERT_FALSE(camera.ok());
  EXPECT_EQ(camera.status().code(), StatusCode::kUnsupported);
  EXPECT_TRUE(contains(camera.status().message(), "not a video capture device")) << camera.status().message();
  driver_.caps = V4L2_CAP_VIDEO_CAPTURE | V4L2_CAP_READWRITE;
  camera = V4l2Camera::open(options(), driver_);
  ASSERT_FALSE(camera.ok());
  EXPECT_EQ(camera.status().code(), StatusCode::kUnsupported);
  EXPECT_TRUE(contains(camera.status().message(), "cannot stream")) << camera.status().message();
}

TEST_F(V4l2CameraFake, CharacterDeviceOfAnotherMajorIsNotAV4l2Device) {
  driver_.device_major = 189;  // a USB device node, say
  auto camera = V4l2Camera::open(options(), driver_);
  ASSERT_FALSE(camera.ok());
  EXPECT_EQ(camera.status().code(), StatusCode::kInvalidArgument);
  EXPECT_TRUE(contains(camera.status().message(), "189:42")) << camera.status().message();
  EXPECT_EQ(driver_.open_fds, 0);
}

TEST_F(V4l2CameraFake, FrameRateIsAskedFor) {
  V4l2CameraOptions o = options();
  o.fps = 15;
  auto camera = open_ok(o);
  ASSERT_NE(camera, nullptr);
  EXPECT_EQ(driver_.fps_denominator, 15u);
  EXPECT_DOUBLE_EQ(camera->fps(), 15.0);
  camera.reset();
  driver_.timeperframe = false;
  driver_.fps_denominator = 0;
  camera = open_ok(o);
  ASSERT_NE(camera, nullptr);
  EXPECT_TRUE(contains(camera->describe(), "cannot set 15 fps")) << camera->describe();
}

TEST_F(V4l2CameraFake, YuyvFramesAreDeinterleavedIntoPooledGrey) {
  driver_.padding = 6;
  add_shots(5);
  auto camera = start_ok();
  ASSERT_NE(camera, nullptr);
  EXPECT_EQ(camera->poll_fd(), 77);
  for (int i = 0; i < 5; ++i) {
    hal::Frame f;
    Status s = camera->acquire(f, 100);
    ASSERT_TRUE(s.ok()) << s.to_string();
    EXPECT_EQ(f.image.width, 64);
    EXPECT_EQ(f.image.height, 48);
    EXPECT_EQ(f.image.stride % 16, 0);  // pooled rows are NEON-aligned
    EXPECT_EQ(mismatches(f, static_cast<std::uint8_t>(10 * i)), 0) << "frame " << i;
    EXPECT_EQ(f.sequence, static_cast<std::uint64_t>(i));
    EXPECT_EQ(f.timestamp_ns, 1000000000 + 33000000 * static_cast<std::int64_t>(i));
    EXPECT_FALSE(f.exposure_us.has_value());
    ASSERT_TRUE(camera->release(f).ok());
  }
  EXPECT_EQ(camera->stats().delivered, 5u);
  EXPECT_EQ(camera->stats().dropped, 0u);
  EXPECT_EQ(camera->stats().buffers_high_water, 1u) << "one frame lent at a time";
  EXPECT_TRUE(contains(camera->describe(), "YUYV (luma de-interleaved")) << camera->describe();
}

TEST_F(V4l2CameraFake, GreyFramesLendTheMappedBufferItself) {
  driver_.formats = {V4L2_PIX_FMT_GREY};
  driver_.padding = 3;
  add_shots(2);
  auto camera = start_ok();
  ASSERT_NE(camera, nullptr);
  hal::Frame f;
  ASSERT_TRUE(camera->acquire(f, 100).ok());
  ASSERT_GE(f.buffer_index, 0);
  EXPECT_EQ(f.image.data, driver_.memory[static_cast<std::size_t>(f.buffer_index)].data());
  EXPECT_EQ(f.image.stride, 64 + 3);
  EXPECT_EQ(mismatches(f, 0), 0);
  ASSERT_TRUE(camera->release(f).ok());
}

TEST_F(V4l2CameraFake, MultiplanarNv12TakesTheYPlane) {
  driver_.caps = V4L2_CAP_VIDEO_CAPTURE_MPLANE | V4L2_CAP_STREAMING;
  driver_.formats = {V4L2_PIX_FMT_NV12M};
  add_shots(2);
  auto camera = start_ok();
  ASSERT_NE(camera, nullptr);
  hal::Frame f;
  Status s = camera->acquire(f, 100);
  ASSERT_TRUE(s.ok()) << s.to_string();
  EXPECT_EQ(mismatches(f, 0), 0);
  EXPECT_TRUE(contains(camera->describe(), "multi-planar")) << camera->describe();
  ASSERT_TRUE(camera->release(f).ok());
}

TEST_F(V4l2CameraFake, SequenceGapsCountAsDropped) {
  for (std::uint32_t seq : {7u, 8u, 11u, 12u, 20u})
    driver_.shots.push_back({seq, 0, 0, false, ~0u, nullptr});
  auto camera = start_ok();
  ASSERT_NE(camera, nullptr);
  std::vector<std::uint64_t> got;
  hal::Frame f;
  while (camera->acquire(f, 10).ok()) {
    got.push_back(f.sequence);
    ASSERT_TRUE(camera->release(f).ok());
  }
  EXPECT_EQ(got, (std::vector<std::uint64_t>{0, 1, 4, 5, 13}));
  EXPECT_EQ(camera->stats().dropped, 2u + 7u);
}

TEST_F(V4l2CameraFake, TornAndShortFramesAreRequeuedAndCounted) {
  add_shots(4);
  driver_.shots[1].error = true;
  driver_.shots[2].bytes_used = 100;
  auto camera = start_ok();
  ASSERT_NE(camera, nullptr);
  hal::Frame f;
  ASSERT_TRUE(camera->acquire(f, 10).ok());
  ASSERT_TRUE(camera->release(f).ok());
  ASSERT_TRUE(camera->acquire(f, 10).ok());
  EXPECT_EQ(f.sequence, 3u);
  EXPECT_EQ(mismatches(f, 30), 0);
  EXPECT_EQ(camera->stats().dropped, 2u);
  EXPECT_EQ(driver_.queued.size(), 2u);  // the two bad buffers went straight back
  ASSERT_TRUE(camera->release(f).ok());
}

TEST_F(V4l2CameraFake, EveryBufferLentIsOutOfMemoryUntilOneIsReleased) {
  add_shots(5);
  auto camera = start_ok();
  ASSERT_NE(camera, nullptr);
  hal::Frame frames[3];
  for (hal::Frame& f : frames) ASSERT_TRUE(camera->acquire(f, 10).ok());
  hal::Frame extra;
  EXPECT_EQ(camera->acquire(extra, 10).code(), StatusCode::kOutOfMemory);
  ASSERT_TRUE(camera->release(frames[1]).ok());
  EXPECT_EQ(camera->release(frames[1]).code(), StatusCode::kInvalidArgument);  // twice
  ASSERT_TRUE(camera->acquire(extra, 10).ok());
  EXPECT_EQ(extra.buffer_index, frames[1].buffer_index);
  // The other lent frames were not overwritten.
  EXPECT_EQ(mismatches(frames[0], 0), 0);
  EXPECT_EQ(mismatches(frames[2], 20), 0);
  EXPECT_EQ(mismatches(extra, 30), 0);
  EXPECT_EQ(camera->stats().buffers, 3u);
  EXPECT_EQ(camera->stats().buffers_high_water, 3u);
}

TEST_F(V4l2CameraFake, NothingArrivingIsATimeout) {
  auto camera = start_ok();
  ASSERT_NE(camera, nullptr);
  hal::Frame f;
  Status s = camera->acquire(f, 5);
  EXPECT_EQ(s.code(), StatusCode::kTimeout) << s.to_string();
}

TEST_F(V4l2CameraFake, AcquireBeforeStartIsRejected) {
  auto camera = open_ok(options());
  ASSERT_NE(camera, nullptr);
  hal::Frame f;
  EXPECT_EQ(camera->acquire(f, 5).code(), StatusCode::kInvalidArgument);
}

TEST_F(V4l2CameraFake, VanishingCameraIsUnavailableNamingTheDevice) {
  add_shots(5);
  driver_.vanish_after = 2;
  auto camera = start_ok();
  ASSERT_NE(camera, nullptr);
  hal::Frame f1, f2, f3;
  ASSERT_TRUE(camera->acquire(f1, 10).ok());
  ASSERT_TRUE(camera->release(f1).ok());
  ASSERT_TRUE(camera->acquire(f2, 10).ok());
  Status s = camera->acquire(f3, 10);
  EXPECT_EQ(s.code(), StatusCode::kUnavailable) << s.to_string();
  EXPECT_TRUE(contains(s.message(), driver_.path)) << s.message();
  EXPECT_EQ(camera->acquire(f3, 10).code(), StatusCode::kUnavailable);  // and stays so
  EXPECT_TRUE(camera->release(f2).ok());
  EXPECT_TRUE(contains(camera->describe(), "GONE"));
  EXPECT_EQ(camera->stats().errors, 1u);
  EXPECT_TRUE(camera->stop().ok());
  EXPECT_EQ(driver_.mapped, 0);
  camera.reset();
  EXPECT_EQ(driver_.open_fds, 0);
}

TEST_F(V4l2CameraFake, PollErrorWhileStreamingIsUnavailable) {
  auto camera = start_ok();
  ASSERT_NE(camera, nullptr);
  driver_.poll_error = true;
  hal::Frame f;
  Status s = camera->acquire(f, 10);
  EXPECT_EQ(s.code(), StatusCode::kUnavailable) << s.to_string();
  EXPECT_TRUE(contains(s.message(), driver_.path)) << s.message();
}

TEST_F(V4l2CameraFake, StopUnmapsAndFreesAndStartWorksAgain) {
  add_shots(2);
  auto camera = start_ok();
  ASSERT_NE(camera, nullptr);
  EXPECT_EQ(driver_.mapped, 3);
  hal::Frame f;
  ASSERT_TRUE(camera->acquire(f, 10).ok());
  ASSERT_TRUE(camera->release(f).ok());
  ASSERT_TRUE(camera->stop().ok());
  EXPECT_EQ(driver_.mapped, 0);
  EXPECT_FALSE(driver_.streaming);
  EXPECT_TRUE(driver_.memory.empty());
  ASSERT_TRUE(camera->start().ok());
  ASSERT_TRUE(camera->acquire(f, 10).ok());
  EXPECT_EQ(f.sequence, 1u);  // sequences keep increasing across a restart
  ASSERT_TRUE(camera->release(f).ok());
}

TEST_F(V4l2CameraFake, ExposureIsReadWhenTheDriverHasIt) {
  driver_.has_exposure = true;
  driver_.exposure = 42;  // x 100 us
  add_shots(1);
  auto camera = start_ok();
  ASSERT_NE(camera, nullptr);
  hal::Frame f;
  ASSERT_TRUE(camera->acquire(f, 10).ok());
  ASSERT_TRUE(f.exposure_us.has_value());
  EXPECT_EQ(*f.exposure_us, 4200);
  ASSERT_TRUE(camera->release(f).ok());
}

TEST_F(V4l2CameraFake, ManualExposureIsSetOrRefusedClearly) {
  V4l2CameraOptions o = options();
  o.exposure_us = 8000;
  auto missing = V4l2Camera::open(o, driver_);
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.status().code(), StatusCode::kUnsupported);
  EXPECT_TRUE(contains(missing.status().message(), "exposure_us")) << missing.status().message();

  driver_.has_exposure = true;
  auto camera = open_ok(o);
  ASSERT_NE(camera, nullptr);
  EXPECT_EQ(driver_.exposure, 80);
  camera.reset();

  o.exposure_us = 600000;
  auto too_long = V4l2Camera::open(o, driver_);
  ASSERT_FALSE(too_long.ok());
  EXPECT_EQ(too_long.status().code(), StatusCode::kInvalidArgument);
  EXPECT_TRUE(contains(too_long.status().message(), "[100, 500000]")) << too_long.status().message();

  o.exposure_us.reset();
  o.gain = 4;  // the fake has no gain control
  auto no_gain = V4l2Camera::open(o, driver_);
  ASSERT_FALSE(no_gain.ok());
  EXPECT_EQ(no_gain.status().code(), StatusCode::kUnsupported);
}

TEST_F(V4l2CameraFake, WallClockTimestampsAreReplacedByTheDequeueTime) {
  driver_.monotonic = false;
  add_shots(1);
  auto camera = start_ok();
  ASSERT_NE(camera, nullptr);
  const std::int64_t before = MonotonicClock().now_ns();
  hal::Frame f;
  ASSERT_TRUE(camera->acquire(f, 10).ok());
  EXPECT_GE(f.timestamp_ns, before);
  EXPECT_LE(f.timestamp_ns, MonotonicClock().now_ns());
  EXPECT_TRUE(contains(camera->describe(), "not CLOCK_MONOTONIC")) << camera->describe();
  ASSERT_TRUE(camera->release(f).ok());
}

TEST_F(V4l2CameraFake, TooFewBuffersGrantedIsOutOfMemory) {
  driver_.grant_buffers = 1;
  auto camera = open_ok(options());
  ASSERT_NE(camera, nullptr);
  Status s = camera->start();
  EXPECT_EQ(s.code(), StatusCode::kOutOfMemory) << s.to_string();
  EXPECT_EQ(driver_.mapped, 0);
}

}  // namespace
}  // namespace ale::linux_hal
