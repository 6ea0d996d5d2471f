// Intensity-centroid moments, scalar: the specification orientation_neon.cpp reproduces
// (orientation.h), and the angle the extractor takes from them (brief.h).
#include "core/features/orientation.h"

#include <array>
#include <cmath>

#include "core/features/brief.h"
#include "core/features/kernels.h"

namespace ale::features {

namespace {

struct DiskRows {
  std::array<int, kPatchRadius + 1> u{};
  DiskRows() {
    for (int v = 0; v <= kPatchRadius; ++v) u[static_cast<std::size_t>(v)] = disk_half_width(v);
  }
};
const DiskRows kDisk;

}  // namespace

int disk_half_width(int v) {
  int u = 0;
  while ((u + 1) * (u + 1) + v * v <= kPatchRadius * kPatchRadius + kPatchRadius) ++u;
  return u;
}

namespace internal {

Moments ic_moments_ref(GrayView image, int x, int y) {
  // Rows v and -v share one pass.
  const std::uint8_t* centre = image.row(y) + x;
  Moments m;
  for (int u = -kPatchRadius; u <= kPatchRadius; ++u) m.m10 += u * centre[u];
  for (int v = 1; v <= kPatchRadius; ++v) {
    const int half = kDisk.u[static_cast<std::size_t>(v)];
    const std::uint8_t* below = centre + v * image.stride;
    const std::uint8_t* above = centre - v * image.stride;
    int diff = 0;
    for (int u = -half; u <= half; ++u) {
      const int b = below[u];
      const int t = above[u];
      diff += b - t;
      m.m10 += u * (b + t);
    }
    m.m01 += v * diff;
  }
  return m;
}

}  // namespace internal

Moments ic_moments(GrayView image, int x, int y, KernelPath path) { return kernels(path).ic_moments(image, x, y); }

float ic_angle_deg(GrayView image, int x, int y) {
  const Moments m = ic_moments(image, x, y);
  float deg = static_cast<float>(std::atan2(static_cast<double>(m.m01), static_cast<double>(m.m10)) * (180.0 / M_PI));
  if (deg < 0.0f) deg += 360.0f;
  if (deg >= 360.0f) deg -= 360.0f;
  return deg;
}

}  // namespace ale::features
