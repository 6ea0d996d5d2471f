// Camera HAL: a source of 8-bit grey frames. Backends: V4L2 (robot), replay of recorded
// datasets (host and robot), fake (tests).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include "core/base/image.h"
#include "core/base/status.h"

namespace ale::hal {

enum class DistortionModel { kNone, kRadialTangential, kEquidistant };

// Pinhole intrinsics with lens distortion and the camera-to-body transform, as far as the
// backend knows them (a V4L2 camera knows none until a calibration file is loaded).
struct CameraCalibration {
  int width = 0;
  int height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  DistortionModel distortion_model = DistortionModel::kNone;
  std::array<double, 4> distortion{};  // radtan: k1 k2 p1 p2; equidistant: k1..k4
  std::array<double, 16> T_BS{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};  // row-major 4x4
  double rate_hz = 0;
};

// A frame lent by the camera. `image` stays valid until the frame is released.
struct Frame {
  GrayView image;
  std::int64_t timestamp_ns = 0;   // capture time on the camera's clock
  std::uint64_t sequence = 0;      // 0, 1, 2... in capture order; a gap means dropped frames
  std::optional<int> exposure_us;  // when the backend knows it
  int buffer_index = -1;           // which pooled buffer backs the frame (for release)
};

struct CameraStats {
  std::uint64_t delivered = 0;
  std::uint64_t dropped = 0;   // frames the backend lost (sequence gaps, decode failures skipped)
  std::uint64_t errors = 0;
  std::uint64_t buffers = 0;             // frame buffers the backend has
  std::uint64_t buffers_high_water = 0;  // most of them lent out at once so far
};

class Camera {
 public:
  virtual ~Camera() = default;

  virtual Status start() = 0;
  virtual Status stop() = 0;

  // Waits up to timeout_ms for the next frame and lends it. kEndOfStream when a replay is over,
  // kTimeout when nothing arrived, kUnavailable when the device went away, kOutOfMemory when every
  // buffer is still lent out.
  virtual Status acquire(Frame& frame, int timeout_ms) = 0;
  // Gives a lent frame's buffer back.
  virtual Status release(const Frame& frame) = 0;

  // What the backend knows of the lens; kUnsupported when it knows nothing.
  virtual Result<CameraCalibration> calibration() const { return unsupported("camera has no calibration"); }
  // A descriptor that becomes readable when a frame is ready, for poll(); -1 when there is none
  // (acquire() then does not block on I/O).
  virtual int poll_fd() const { return -1; }
  virtual CameraStats stats() const { return {}; }
  virtual std::string describe() const = 0;
};

}  // namespace ale::hal
