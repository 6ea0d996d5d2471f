#include "app/tools/lib/render/texture.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "app/tools/lib/render/rng.h"

namespace ale::render {

namespace {

GrayImage half_size(const GrayImage& src) {
  const int w = std::max(1, src.width / 2);
  const int h = std::max(1, src.height / 2);
  GrayImage dst(w, h);
  for (int y = 0; y < h; ++y) {
    const int y0 = std::min(2 * y, src.height - 1);
    const int y1 = std::min(2 * y + 1, src.height - 1);
    const std::uint8_t* r0 = src.pixels.data() + static_cast<std::size_t>(y0) * static_cast<std::size_t>(src.width);
    const std::uint8_t* r1 = src.pixels.data() + static_cast<std::size_t>(y1) * static_cast<std::size_t>(src.width);
    std::uint8_t* out = dst.pixels.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(w);
    for (int x = 0; x < w; ++x) {
      const int x0 = std::min(2 * x, src.width - 1);
      const int x1 = std::min(2 * x + 1, src.width - 1);
      out[x] = static_cast<std::uint8_t>((r0[x0] + r0[x1] + r1[x0] + r1[x1] + 2) >> 2);
    }
  }
  return dst;
}

inline float smooth(float t) { return t * t * (3.0f - 2.0f * t); }

}  // namespace

Texture::Texture(GrayImage level0, float texel_m, bool repeat)
    : texel_m_(texel_m), inv_texel_m_(1.0f / texel_m), repeat_(repeat) {
  levels_.push_back(std::move(level0));
  while (levels_.back().width > 1 || levels_.back().height > 1) levels_.push_back(half_size(levels_.back()));
}

float Texture::bilinear(int level, float x, float y) const {
  const GrayImage& img = levels_[static_cast<std::size_t>(level)];
  // Texel centres sit at half-integers.
  x -= 0.5f;
  y -= 0.5f;
  const float fx = std::floor(x);
  const float fy = std::floor(y);
  const float ax = x - fx;
  const float ay = y - fy;
  int x0 = static_cast<int>(fx);
  int y0 = static_cast<int>(fy);
  int x1 = x0 + 1;
  int y1 = y0 + 1;
  const int w = img.width;
  const int h = img.height;
  if (repeat_) {
    auto wrap = [](int v, int n) {
      v %= n;
      return v < 0 ? v + n : v;
    };
    x0 = wrap(x0, w);
    x1 = wrap(x1, w);
    y0 = wrap(y0, h);
    y1 = wrap(y1, h);
  } else {
    x0 = std::clamp(x0, 0, w - 1);
    x1 = std::clamp(x1, 0, w - 1);
    y0 = std::clamp(y0, 0, h - 1);
    y1 = std::clamp(y1, 0, h - 1);
  }
  const std::uint8_t* r0 = img.pixels.data() + static_cast<std::size_t>(y0) * static_cast<std::size_t>(w);
  const std::uint8_t* r1 = img.pixels.data() + static_cast<std::size_t>(y1) * static_cast<std::size_t>(w);
  const float top = static_cast<float>(r0[x0]) + ax * static_cast<float>(r0[x1] - r0[x0]);
  const float bottom = static_cast<float>(r1[x0]) + ax * static_cast<float>(r1[x1] - r1[x0]);
  return top + ay * (bottom - top);
}

float Texture::sample(float u_m, float v_m, float footprint_m) const {
  constexpr float kInv255 = 1.0f / 255.0f;
  const float lod = std::log2(std::max(footprint_m * inv_texel_m_, 1.0f));
  const int top_level = levels() - 1;
  const float clamped = std::min(lod, static_cast<float>(top_level));
  const int l0 = static_cast<int>(clamped);
  const float frac = clamped - static_cast<float>(l0);
  const float s0 = std::ldexp(1.0f, -l0);
  const float x = u_m * inv_texel_m_;
  const float y = v_m * inv_texel_m_;
  const float a = bilinear(l0, x * s0, y * s0);
  if (frac <= 0.0f || l0 >= top_level) return a * kInv255;
  const float b = bilinear(l0 + 1, x * s0 * 0.5f, y * s0 * 0.5f);
  return (a + frac * (b - a)) * kInv255;
}

float value_noise(float x, float y, std::uint32_t seed) {
  const float fx = std::floor(x);
  const float fy = std::floor(y);
  const auto ix = static_cast<std::int32_t>(fx);
  const auto iy = static_cast<std::int32_t>(fy);
  const float tx = smooth(x - fx);
  const float ty = smooth(y - fy);
  constexpr float kInv = 1.0f / 4294967296.0f;
  const float v00 = static_cast<float>(hash_2d(ix, iy, seed)) * kInv;
  const float v10 = static_cast<float>(hash_2d(ix + 1, iy, seed)) * kInv;
  const float v01 = static_cast<float>(hash_2d(ix, iy + 1, seed)) * kInv;
  const float v11 = static_cast<float>(hash_2d(ix + 1, iy + 1, seed)) * kInv;
  const float top = v00 + tx * (v10 - v00);
  const float bottom = v01 + tx * (v11 - v01);
  return top + ty * (bottom - top);
}

float fractal_noise(float x, float y, int octaves, std::uint32_t seed) {
  float sum = 0.0f;
  float amplitude = 1.0f;
  float total = 0.0f;
  for (int o = 0; o < octaves; ++o) {
    sum += amplitude * value_noise(x, y, seed + static_cast<std::uint32_t>(o) * 7919u);
    total += amplitude;
    x *= 2.0f;
    y *= 2.0f;
    amplitude *= 0.5f;
  }
  return sum / total;
}

}  // namespace ale::render
