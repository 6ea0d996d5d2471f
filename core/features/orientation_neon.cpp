// NEON intensity-centroid moments, bit-exact with ic_moments_ref() (orientation.h). Lane j of the
// 32-pixel window is u = j - 15. Per pair of rows v, -v, masked to the disk: S[j] += b + t (at most
// 31 * 255 over the disk, u16) and D[j] += v (b - t) (|D[j]| <= 120 * 255 < 2^15: the u16
// multiply-accumulate wraps but the final lane is exact read as s16). Then m10 = sum (j - 15) S[j]
// and m01 = sum D[j].
#include "core/features/orientation.h"

#include <array>

#include "core/features/brief.h"

#if defined(__ARM_NEON)
#include <arm_neon.h>

namespace ale::features::internal {

namespace {

struct DiskMasks {
  alignas(16) std::uint8_t row[kPatchRadius + 1][32] = {};
  alignas(16) std::int16_t u[32] = {};
  DiskMasks() {
    for (int v = 0; v <= kPatchRadius; ++v) {
      const int half = disk_half_width(v);
      for (int j = 0; j < 32; ++j) row[v][j] = (j - kPatchRadius >= -half && j - kPatchRadius <= half) ? 0xFF : 0;
    }
    for (int j = 0; j < 32; ++j) u[j] = static_cast<std::int16_t>(j - kPatchRadius);
  }
};

inline int sum_s32(int32x4_t v) {
  const int32x2_t s = vadd_s32(vget_low_s32(v), vget_high_s32(v));
  return vget_lane_s32(vpadd_s32(s, s), 0);
}

}  // namespace

Moments ic_moments_neon(GrayView image, int x, int y) {
  static_assert(kPatchRadius == 15, "the 32-pixel window holds the disk of radius 15");
  if (x + 16 >= image.width) return ic_moments_ref(image, x, y);
  static const DiskMasks kMasks;
  const std::uint8_t* left = image.row(y) + x - kPatchRadius;
  uint16x8_t s[4], d[4];
  {
    const uint8x16_t m1 = vld1q_u8(kMasks.row[0] + 16);
    const uint8x16_t c0 = vld1q_u8(left);
    const uint8x16_t c1 = vandq_u8(vld1q_u8(left + 16), m1);
    s[0] = vmovl_u8(vget_low_u8(c0));
    s[1] = vmovl_u8(vget_high_u8(c0));
    s[2] = vmovl_u8(vget_low_u8(c1));
    s[3] = vmovl_u8(vget_high_u8(c1));
    for (int k = 0; k < 4; ++k) d[k] = vdupq_n_u16(0);
  }
  for (int v = 1; v <= kPatchRadius; ++v) {
    const std::uint8_t* below = left + v * image.stride;
    const std::uint8_t* above = left - v * image.stride;
    const uint8x16_t m0 = vld1q_u8(kMasks.row[v]);
    const uint8x16_t m1 = vld1q_u8(kMasks.row[v] + 16);
    const uint8x16_t b0 = vandq_u8(vld1q_u8(below), m0);
    const uint8x16_t b1 = vandq_u8(vld1q_u8(below + 16), m1);
    const uint8x16_t t0 = vandq_u8(vld1q_u8(above), m0);
    const uint8x16_t t1 = vandq_u8(vld1q_u8(above + 16), m1);
    const uint8x8_t w = vdup_n_u8(static_cast<std::uint8_t>(v));
    s[0] = vaddw_u8(vaddw_u8(s[0], vget_low_u8(b0)), vget_low_u8(t0));
    s[1] = vaddw_u8(vaddw_u8(s[1], vget_high_u8(b0)), vget_high_u8(t0));
    s[2] = vaddw_u8(vaddw_u8(s[2], vget_low_u8(b1)), vget_low_u8(t1));
    s[3] = vaddw_u8(vaddw_u8(s[3], vget_high_u8(b1)), vget_high_u8(t1));
    d[0] = vmlsl_u8(vmlal_u8(d[0], vget_low_u8(b0), w), vget_low_u8(t0), w);
    d[1] = vmlsl_u8(vmlal_u8(d[1], vget_high_u8(b0), w), vget_high_u8(t0), w);
    d[2] = vmlsl_u8(vmlal_u8(d[2], vget_low_u8(b1), w), vget_low_u8(t1), w);
    d[3] = vmlsl_u8(vmlal_u8(d[3], vget_high_u8(b1), w), vget_high_u8(t1), w);
  }
  int32x4_t m10 = vdupq_n_s32(0);
  int32x4_t m01 = vdupq_n_s32(0);
  for (int k = 0; k < 4; ++k) {
    const int16x8_t sk = vreinterpretq_s16_u16(s[k]);
    const int16x8_t uk = vld1q_s16(kMasks.u + 8 * k);
    m10 = vmlal_s16(m10, vget_low_s16(sk), vget_low_s16(uk));
    m10 = vmlal_s16(m10, vget_high_s16(sk), vget_high_s16(uk));
    m01 = vpadalq_s16(m01, vreinterpretq_s16_u16(d[k]));
  }
  return {sum_s32(m10), sum_s32(m01)};
}

}  // namespace ale::features::internal

#endif  // __ARM_NEON
