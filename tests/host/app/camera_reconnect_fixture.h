// The camera-loss fixture of the daemon's loop tests: a V4L2 camera whose driver (the in-memory
// FakeV4l2Driver behind the injectable system-call layer) is unplugged after its first shots and
// plugged back in after a set time, on a fake clock that the loop's waits advance. The shots are
// a pattern (camera_reconnect_test.cpp) or rendered frames (rendered_map_test.cpp).
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "app/daemon/frame_loop.h"
#include "hal/linux/v4l2_camera.h"
#include "tests/host/app/loop_fixtures.h"
#include "tests/host/hal/linux/fake_v4l2_driver.h"

namespace ale::test {

constexpr std::int64_t kMsNs = 1000000;

class CameraReconnectFixture : public ::testing::Test {
 protected:
  void SetUp() override {
    options_.device = driver_.path;
    options_.width = 64;
    options_.height = 48;
    first_shots();
    auto cam = linux_hal::V4l2Camera::open(options_, driver_);
    ASSERT_TRUE(cam.ok()) << cam.status().to_string();
    camera_ = std::move(*cam);
    config_.camera.reconnect_initial_ms = 250;
    config_.camera.reconnect_max_ms = 1000;
    config_.camera.reconnect_give_up_ms = 10000;
  }

  // The shots before the loss (and when it happens), and those after the device is back:
  // five pattern frames each, unplugged after the fifth.
  virtual void first_shots() {
    add_shots(5, 0);
    driver_.vanish_after = 5;
  }
  virtual void replugged_shots() { add_shots(5, 10000 * kMsNs); }

  void add_shots(int n, std::int64_t t0_ns) {
    for (int i = 0; i < n; ++i) {
      FakeV4l2Driver::Shot shot;
      shot.sequence = static_cast<std::uint32_t>(i);
      shot.timestamp_ns = t0_ns + i * 33 * kMsNs;
      shot.seed = static_cast<std::uint8_t>(i);
      driver_.shots.push_back(shot);
    }
  }

  // A lens for the 64x48 frames (the pipeline needs one; these tests exercise the loop).
  static hal::CameraCalibration lens() { return ale::test::test_lens(); }

  // The board's part: close the old camera, open the device again.
  Result<hal::Camera*> reopen() {
    ++reopen_calls_;
    camera_.reset();
    auto cam = linux_hal::V4l2Camera::open(options_, driver_);
    if (!cam.ok()) return cam.status();
    camera_ = std::move(*cam);
    return camera_.get();
  }

  app::LoopDeps deps(hal::PoseSink& sink) {
    app::LoopDeps d{*camera_, sink, gpio_};
    d.calibration = calibration_;
    d.reopen_camera = [this] { return reopen(); };
    d.clock = &clock_;
    d.wait = [this](std::int64_t wait_ns) {
      if (unplugged_at_ns_ < 0) unplugged_at_ns_ = clock_.now_ns();
      waits_ms_.push_back(wait_ns / kMsNs);
      clock_.advance_ns(wait_ns);
      if (replug_after_ns_ >= 0 && driver_.gone() && clock_.now_ns() - unplugged_at_ns_ >= replug_after_ns_) {
        driver_.replug();
        replugged_shots();
      }
      return false;  // no stop request
    };
    return d;
  }

  FakeV4l2Driver driver_;
  hal::CameraCalibration calibration_ = lens();
  linux_hal::V4l2CameraOptions options_;
  std::unique_ptr<linux_hal::V4l2Camera> camera_;
  hal::ManualClock clock_;
  hal::FakeGpio gpio_;
  app::DaemonConfig config_;
  std::int64_t unplugged_at_ns_ = -1;
  std::int64_t replug_after_ns_ = 3000 * kMsNs;
  std::vector<std::int64_t> waits_ms_;
  int reopen_calls_ = 0;
};

}  // namespace ale::test
