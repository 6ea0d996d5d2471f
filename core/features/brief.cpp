#include "core/features/brief.h"

#include <cmath>
#include <cstring>

#include "core/features/kernels.h"

namespace ale::features {

namespace {

std::uint64_t splitmix64(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

// round(N(0,1) * sigma) with sigma = 31/5, from 12 uniforms in Q16.
int gaussian_coordinate(std::uint64_t& state) {
  std::int64_t sum = 0;
  for (int i = 0; i < 12; ++i) sum += static_cast<std::int64_t>(splitmix64(state) >> 48);
  const std::int64_t z_q16 = sum - 6 * 65536;  // N(0, 1) * 2^16, approximately
  const std::int64_t scaled = z_q16 * 31;       // * sigma * 5 * 2^16
  const std::int64_t denom = 5 * 65536;
  const std::int64_t half = denom / 2;
  return static_cast<int>(scaled >= 0 ? (scaled + half) / denom : -((-scaled + half) / denom));
}

}  // namespace

int hamming_distance(const Descriptor& a, const Descriptor& b, KernelPath path) {
  return kernels(path).hamming(a, b);
}

HammingKernel hamming_kernel(KernelPath path) { return kernels(path).hamming; }

BriefPattern make_brief_pattern(std::uint64_t seed) {
  BriefPattern p;
  std::uint64_t state = seed;
  const auto draw_point = [&](int& x, int& y) {
    do {
      x = gaussian_coordinate(state);
      y = gaussian_coordinate(state);
    } while (x * x + y * y > kPatchRadius * kPatchRadius);
  };
  for (int i = 0; i < kDescriptorBits; ++i) {
    int x0, y0, x1, y1;
    do {
      draw_point(x0, y0);
      draw_point(x1, y1);
    } while (x0 == x1 && y0 == y1);
    const std::size_t k = static_cast<std::size_t>(i) * 4u;
    p.xy[k] = static_cast<std::int8_t>(x0);
    p.xy[k + 1] = static_cast<std::int8_t>(y0);
    p.xy[k + 2] = static_cast<std::int8_t>(x1);
    p.xy[k + 3] = static_cast<std::int8_t>(y1);
  }
  return p;
}

void RotatedPattern::build(const BriefPattern& pattern, int stride) {
  stride_ = stride;
  table_.resize(static_cast<std::size_t>(kAngleBins) * 2u * kDescriptorBits);
  for (int bin = 0; bin < kAngleBins; ++bin) {
    const double a = 2.0 * M_PI * bin / kAngleBins;
    const double c = std::cos(a);
    const double s = std::sin(a);
    const auto offset = [&](int point) {
      const double x = pattern.xy[static_cast<std::size_t>(2 * point)];
      const double y = pattern.xy[static_cast<std::size_t>(2 * point + 1)];
      const int rx = static_cast<int>(std::lround(x * c - y * s));
      const int ry = static_cast<int>(std::lround(x * s + y * c));
      return ry * stride + rx;
    };
    std::int32_t* out = table_.data() + static_cast<std::size_t>(bin) * 2u * kDescriptorBits;
    for (int word = 0; word < kDescriptorBits / 32; ++word) {
      for (int k = 31; k >= 0; --k) {
        const int pair = 32 * word + k;
        *out++ = offset(2 * pair);
        *out++ = offset(2 * pair + 1);
      }
    }
  }
}

// ic_angle_deg(): orientation_ref.cpp.

int angle_bin(float angle_deg) {
  int bin = static_cast<int>(std::lround(static_cast<double>(angle_deg) * kAngleBins / 360.0));
  bin %= kAngleBins;
  return bin < 0 ? bin + kAngleBins : bin;
}

void describe(GrayView smoothed, int x, int y, const RotatedPattern& rotated, int bin, Descriptor& out,
              KernelPath path) {
  kernels(path).describe(smoothed, x, y, rotated, bin, out);
}

}  // namespace ale::features
