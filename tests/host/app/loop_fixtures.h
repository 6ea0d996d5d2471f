// What the frame-loop tests share: a lens for the fake camera's 64x48 frames, and such frames.
#pragma once

#include <cstdint>
#include <vector>

#include "core/base/image.h"
#include "hal/camera.h"

namespace ale::test {

// The pipeline needs a lens; the tests here exercise the loop.
inline hal::CameraCalibration test_lens() {
  hal::CameraCalibration c;
  c.fx = c.fy = 50.0;
  c.cx = 32.0;
  c.cy = 24.0;
  return c;
}

// n flat 64x48 frames of brightness 0, 10, 20...
inline std::vector<GrayImage> frames(int n) {
  std::vector<GrayImage> v;
  for (int i = 0; i < n; ++i) v.emplace_back(64, 48, static_cast<std::uint8_t>(10 * i));
  return v;
}

}  // namespace ale::test
