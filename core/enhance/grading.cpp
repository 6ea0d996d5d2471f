#include "core/enhance/grading.h"

#include <algorithm>
#include <cmath>

#include "core/enhance/clahe.h"

#if defined(__ARM_NEON)
#include <arm_neon.h>
#endif

namespace ale::enhance {

namespace {

// mean, sigma, median and pixel count from the histogram.
void finish_stats(FrameStats& out) {
  std::uint64_t n = 0;
  std::uint64_t sum = 0;
  std::uint64_t sum_sq = 0;
  for (std::size_t i = 0; i < 256; ++i) {
    const std::uint64_t v = i;
    const std::uint64_t c = out.histogram[i];
    n += c;
    sum += c * v;
    sum_sq += c * v * v;
  }
  const Moments m = moments_from_sums(n, sum, sum_sq);
  out.pixels = m.pixels;
  out.mean = m.mean;
  out.sigma = m.sigma;
  out.median = 0;
  if (n == 0) return;
  std::uint64_t cum = 0;
  for (int v = 0; v < 256; ++v) {
    cum += out.histogram[static_cast<std::size_t>(v)];
    if (2 * cum >= n) {
      out.median = v;
      break;
    }
  }
}

}  // namespace

void compute_stats(GrayView image, FrameStats& out) {
  // Two tables for neighbouring pixels: in dark or flat images neighbours share a bin, and
  // increments of one counter in a row wait for each other.
  std::uint32_t sub[2][256] = {};
  for (int y = 0; y < image.height; ++y) count_row(image.row(y), 0, std::max(image.width, 0), sub[0], sub[1]);
  for (std::size_t v = 0; v < 256; ++v) out.histogram[v] = sub[0][v] + sub[1][v];
  finish_stats(out);
}

void stats_from_histogram(FrameStats& out) { finish_stats(out); }


Moments compute_moments(GrayView image) {
  std::uint64_t sum = 0, sum_sq = 0;
  std::uint8_t low = 255;
  const int w = image.width > 0 ? image.width : 0;
  int y = 0;
#if defined(__ARM_NEON)
  if (w >= 16 && w <= 2048) {
    // 16 pixels a step; a row's last step overlaps the previous one with those lanes masked out
    // of the sums. Byte sums in 16-bit lanes (at most 2 * 255 a step) folded into 32-bit lanes
    // before 128 steps, squares in 32-bit lanes (at most 4 * 65025 a step), both folded into the
    // 64-bit totals before 16,000 steps. Small images (the feature cells, 36-42 pixels wide) are
    // the common caller: per row only the loop and the overlapping step, no folding; the step is
    // in inline assembly on 32-bit ARM because GCC 12 adds three q-register copies to its 7
    // instructions.
    static const std::uint8_t kLane[16] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15};
    const int tail = w % 16;
    const uint8x16_t keep =
        vcgeq_u8(vld1q_u8(kLane), vdupq_n_u8(static_cast<std::uint8_t>(tail == 0 ? 0 : 16 - tail)));
    const int steps_per_row = (w + 15) / 16;
    const std::size_t full = static_cast<std::size_t>(w / 16) * 16u;
    uint32x4_t s32 = vdupq_n_u32(0), q32 = vdupq_n_u32(0);
    uint16x8_t s16 = vdupq_n_u16(0);
    uint8x16_t m8 = vdupq_n_u8(255);
    int steps16 = 0, steps32 = 0;
    const auto fold = [&] {
      s32 = vpadalq_u16(s32, s16);
      s16 = vdupq_n_u16(0);
      const uint64x2_t s2 = vpaddlq_u32(s32);
      const uint64x2_t q2 = vpaddlq_u32(q32);
      sum += vgetq_lane_u64(s2, 0) + vgetq_lane_u64(s2, 1);
      sum_sq += vgetq_lane_u64(q2, 0) + vgetq_lane_u64(q2, 1);
      s32 = q32 = vdupq_n_u32(0);
      steps16 = steps32 = 0;
    };
    for (; y < image.height; ++y) {
      const std::uint8_t* p = image.row(y);
      const std::uint8_t* const end = p + full;
#if defined(__arm__)
      uint8x16_t v_scratch;
      uint16x8_t sq_scratch;
      asm volatile(
          "1:\n\t"
          "vld1.8 {%q[v]}, [%[p]]!\n\t"
          "vmin.u8 %q[m8], %q[m8], %q[v]\n\t"
          "vpadal.u8 %q[s16], %q[v]\n\t"
          "vmull.u8 %q[sq], %e[v], %e[v]\n\t"
          "vpadal.u16 %q[q32], %q[sq]\n\t"
          "vmull.u8 %q[sq], %f[v], %f[v]\n\t"
          "vpadal.u16 %q[q32], %q[sq]\n\t"
          "cmp %[p], %[end]\n\t"
          "bne 1b\n\t"
          : [p] "+r"(p), [m8] "+w"(m8), [s16] "+w"(s16), [q32] "+w"(q32), [v] "=&w"(v_scratch),
            [sq] "=&w"(sq_scratch)
          : [end] "r"(end)
          : "cc", "memory");
#else
      for (; p != end; p += 16) {
        const uint8x16_t v = vld1q_u8(p);
        m8 = vminq_u8(m8, v);
        s16 = vpadalq_u8(s16, v);
        q32 = vpadalq_u16(q32, vmull_u8(vget_low_u8(v), vget_low_u8(v)));
        q32 = vpadalq_u16(q32, vmull_u8(vget_high_u8(v), vget_high_u8(v)));
      }
#endif
      if (tail != 0) {
        const uint8x16_t v = vld1q_u8(image.row(y) + w - 16);
        m8 = vminq_u8(m8, v);  // the overlapping lanes were seen already
        const uint8x16_t t = vandq_u8(v, keep);
        s16 = vpadalq_u8(s16, t);
        q32 = vpadalq_u16(q32, vmull_u8(vget_low_u8(t), vget_low_u8(t)));
        q32 = vpadalq_u16(q32, vmull_u8(vget_high_u8(t), vget_high_u8(t)));
      }
      steps16 += steps_per_row;
      steps32 += steps_per_row;
      if (steps32 > 16000 - 128) {
        fold();
      } else if (steps16 > 128 - steps_per_row) {
        s32 = vpadalq_u16(s32, s16);
        s16 = vdupq_n_u16(0);
        steps16 = 0;
      }
    }
    fold();
    uint8x8_t m = vpmin_u8(vget_low_u8(m8), vget_high_u8(m8));
    m = vpmin_u8(m, m);
    m = vpmin_u8(m, m);
    m = vpmin_u8(m, m);
    low = vget_lane_u8(m, 0);
  }
#endif
  for (; y < image.height; ++y) {
    const std::uint8_t* p = image.row(y);
    for (int x = 0; x < w; ++x) {
      const std::uint64_t v = p[x];
      sum += v;
      sum_sq += v * v;
      low = std::min(low, p[x]);
    }
  }
  const std::uint64_t n = static_cast<std::uint64_t>(w) * static_cast<std::uint64_t>(std::max(image.height, 0));
  Moments m = moments_from_sums(n, sum, sum_sq);
  m.min = n == 0 ? 0 : low;
  return m;
}

void remap_stats(const FrameStats& stats, const Lut& lut, FrameStats& out) {
  FrameStats mapped;
  for (std::size_t v = 0; v < 256; ++v) mapped.histogram[lut[v]] += stats.histogram[v];
  finish_stats(mapped);
  out = mapped;
}

namespace {

// Thresholds in dark-to-bright order; class i holds means below thresholds[i] (bright: the rest).
// `shift[i]` moves threshold i: +h when the held class is darker (harder to brighten), -h when
// it is brighter.
BrightnessClass classify_shifted(double mean, const GradingParams& p, const double shift[3]) {
  if (mean < p.t_very_low + shift[0]) return BrightnessClass::kExtremelyDark;
  if (mean < p.t_low + shift[1]) return BrightnessClass::kDark;
  if (mean <= p.t_high + shift[2]) return BrightnessClass::kNormal;
  return BrightnessClass::kBright;
}

}  // namespace

BrightnessClass classify(double mean, const GradingParams& p) {
  const double none[3] = {0.0, 0.0, 0.0};
  return classify_shifted(mean, p, none);
}

BrightnessClass BrightnessGrader::update(double mean) {
  if (!held_) {
    held_ = classify(mean, params_);
    return *held_;
  }
  const int held = static_cast<int>(*held_);  // enum order is dark to bright
  double shift[3];
  for (int i = 0; i < 3; ++i) shift[i] = held <= i ? params_.hysteresis : -params_.hysteresis;
  held_ = classify_shifted(mean, params_, shift);
  return *held_;
}

}  // namespace ale::enhance
