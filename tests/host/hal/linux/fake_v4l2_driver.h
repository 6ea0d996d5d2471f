// A V4L2 capture driver in memory, standing behind the V4l2Io interface, so the camera's
// negotiation, streaming, lending, sequence and vanish handling are tested without a camera.
// It answers the ioctls the way the kernel documentation says a driver does.
#pragma once

#include <linux/videodev2.h>

#include <cstdint>
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "hal/linux/v4l2_io.h"

namespace ale::test {

class FakeV4l2Driver final : public linux_hal::V4l2Io {
 public:
  // One frame the sensor will produce once a buffer is queued and streaming is on.
  struct Shot {
    std::uint32_t sequence = 0;
    std::int64_t timestamp_ns = 0;
    std::uint8_t seed = 0;          // pixel (x, y) has luma pattern(x, y, seed), unless `luma` is set
    bool error = false;             // V4L2_BUF_FLAG_ERROR
    std::uint32_t bytes_used = ~0u; // ~0: a full frame
    std::shared_ptr<const std::vector<std::uint8_t>> luma;  // this image's luma, row by row (width x height)
  };
  static std::uint8_t pattern(int x, int y, std::uint8_t seed) {
    return static_cast<std::uint8_t>(x + 3 * y + seed);
  }

  // --- what the device is (set before the camera opens it)
  std::string path = "/dev/video42";
  unsigned device_major = 81;
  std::uint32_t caps = V4L2_CAP_VIDEO_CAPTURE | V4L2_CAP_STREAMING;
  std::vector<std::uint32_t> formats{V4L2_PIX_FMT_YUYV};
  int max_width = 640;   // S_FMT clamps to these
  int max_height = 480;
  int padding = 0;       // bytes added to each line
  bool timeperframe = true;
  bool monotonic = true;
  bool has_exposure = false;  // V4L2_CID_EXPOSURE_AUTO and _ABSOLUTE, range [1, 5000] (x 100 us)
  std::int32_t exposure = 50;
  std::uint32_t grant_buffers = 0;  // 0: what was asked

  // --- what happens
  std::deque<Shot> shots;
  int vanish_after = -1;  // after this many DQBUFs the device is unplugged (-1: never); its node
                          // is gone too (open() fails) until replug()
  bool poll_error = false;  // poll() reports POLLERR although DQBUF has nothing to say (EAGAIN)

  // --- what was done
  int open_fds = 0;
  int mapped = 0;
  bool streaming = false;
  std::uint32_t format = 0;
  int width = 0;
  int height = 0;
  std::uint32_t fps_denominator = 0;
  int dequeued = 0;
  std::vector<std::uint32_t> queued;  // buffer indices the driver holds
  std::vector<std::vector<std::uint8_t>> memory;

  int open(const char* file, int flags) override;
  int close(int fd) override;
  int fstat(int fd, struct stat* st) override;
  int ioctl(int fd, unsigned long request, void* arg) override;
  void* mmap(std::size_t length, int fd, off_t offset) override;
  int munmap(void* addr, std::size_t length) override;
  int poll(pollfd* fds, nfds_t count, int timeout_ms) override;

  // The device comes back as a fresh one: not streaming, no buffers queued, DQBUF count at 0.
  void replug();

  std::size_t bytes_per_line() const;
  std::size_t frame_bytes() const;
  bool multiplanar() const { return (caps & V4L2_CAP_VIDEO_CAPTURE_MPLANE) != 0; }
  bool gone() const { return vanish_after >= 0 && dequeued >= vanish_after; }

 private:
  static constexpr int kFd = 77;
  int fail(int err);
  void paint(std::vector<std::uint8_t>& buffer, const Shot& shot) const;
  int dequeue(v4l2_buffer& b);
};

}  // namespace ale::test
