// A camera that serves frames from memory, for tests of everything above the HAL.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/base/image.h"
#include "core/base/memory_pool.h"
#include "hal/camera.h"

namespace ale::hal {

class FakeCamera final : public Camera {
 public:
  struct Options {
    int buffers = 3;                  // frames that can be lent at once
    std::int64_t period_ns = 33333333; // timestamps: first at 0, then every period
    int vanish_after = -1;            // after this many frames acquire() says kUnavailable (-1: never)
    int poll_fd = -1;                 // returned by poll_fd(), to test waiting on a silent camera
  };

  // Serves `frames` in order, then kEndOfStream. All frames must have the same size.
  FakeCamera(std::vector<GrayImage> frames, Options options);
  FakeCamera(std::vector<GrayImage> frames) : FakeCamera(std::move(frames), Options{}) {}

  Status start() override;
  Status stop() override;
  Status acquire(Frame& frame, int timeout_ms) override;
  Status release(const Frame& frame) override;
  CameraStats stats() const override {
    CameraStats s = stats_;
    s.buffers = pool_.stats().capacity;
    s.buffers_high_water = pool_.stats().high_water;
    return s;
  }
  int poll_fd() const override { return options_.poll_fd; }
  std::string describe() const override { return "fake camera"; }
  const BlockPool& pool() const { return pool_; }

 private:
  std::vector<GrayImage> frames_;
  Options options_;
  BlockPool pool_;
  std::vector<PooledImage> lent_;  // index = buffer_index
  std::size_t next_ = 0;
  bool started_ = false;
  CameraStats stats_;
};

}  // namespace ale::hal
