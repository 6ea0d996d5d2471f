// NEON helpers shared by the FAST-9 kernels (fast_neon.cpp, score_map_neon.cpp); ARM only.
#pragma once

#if defined(__ARM_NEON)
#include <arm_neon.h>

#include <cstdint>

namespace ale::features::internal {

// Folded to one 32-bit lane: GCC moves a 64-bit lane to core registers through the stack.
inline bool any_lane(uint8x16_t v) {
  const uint32x2_t folded = vreinterpret_u32_u8(vorr_u8(vget_low_u8(v), vget_high_u8(v)));
  return vget_lane_u32(vpmax_u32(folded, folded), 0) != 0;
}

// The compass test of 16 candidates at p (row stride `stride`, threshold t): lanes
// where two neighbouring compass points (0-4, 4-8, 8-12, 12-0) are brighter than c + t, resp.
// darker than c - t, which every arc of 9 contains. Saturation is exact here: c + t > 255 leaves
// no brighter pixel, c - t < 0 no darker one. "Some neighbouring pair both brighter" is
// min(max(c0, c8), max(c4, c12)) > c + t, which takes 4 operations per polarity instead of 7.
struct Compass {
  uint8x16_t c, hi, lo, maybe_bright, maybe_dark;
};

inline Compass compass(const std::uint8_t* p, int stride, uint8x16_t t) {
  Compass r;
  r.c = vld1q_u8(p);
  r.hi = vqaddq_u8(r.c, t);
  r.lo = vqsubq_u8(r.c, t);
  const uint8x16_t v0 = vld1q_u8(p - 3 * stride);
  const uint8x16_t v4 = vld1q_u8(p + 3);
  const uint8x16_t v8 = vld1q_u8(p + 3 * stride);
  const uint8x16_t v12 = vld1q_u8(p - 3);
  r.maybe_bright = vcgtq_u8(vminq_u8(vmaxq_u8(v0, v8), vmaxq_u8(v4, v12)), r.hi);
  r.maybe_dark = vcltq_u8(vmaxq_u8(vminq_u8(v0, v8), vminq_u8(v4, v12)), r.lo);
  return r;
}

}  // namespace ale::features::internal

#endif
