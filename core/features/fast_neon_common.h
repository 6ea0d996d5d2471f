// NEON helpers shared by the FAST-9 kernels (fast_neon.cpp, score_map_neon.cpp); ARM only.
#pragma once

#if defined(__ARM_NEON)
#include <arm_neon.h>

#include <cstdint>

namespace ale::features::internal {

inline bool any_lane(uint8x16_t v) {
  const uint8x8_t folded = vorr_u8(vget_low_u8(v), vget_high_u8(v));
  return vget_lane_u64(vreinterpret_u64_u8(folded), 0) != 0;
}

// The compass test of 16 candidates at p (offsets off[0..15] of the circle, threshold t): lanes
// where two neighbouring compass points (0-4, 4-8, 8-12, 12-0) are brighter than c + t, resp.
// darker than c - t, which every arc of 9 contains. Saturation is exact here: c + t > 255 leaves
// no brighter pixel, c - t < 0 no darker one.
struct Compass {
  uint8x16_t c, hi, lo, maybe_bright, maybe_dark;
};

inline Compass compass(const std::uint8_t* p, const int off[16], uint8x16_t t) {
  Compass r;
  r.c = vld1q_u8(p);
  r.hi = vqaddq_u8(r.c, t);
  r.lo = vqsubq_u8(r.c, t);
  const uint8x16_t v0 = vld1q_u8(p + off[0]);
  const uint8x16_t v4 = vld1q_u8(p + off[4]);
  const uint8x16_t v8 = vld1q_u8(p + off[8]);
  const uint8x16_t v12 = vld1q_u8(p + off[12]);
  r.maybe_bright = vandq_u8(vorrq_u8(vcgtq_u8(v0, r.hi), vcgtq_u8(v8, r.hi)),
                            vorrq_u8(vcgtq_u8(v4, r.hi), vcgtq_u8(v12, r.hi)));
  r.maybe_dark = vandq_u8(vorrq_u8(vcltq_u8(v0, r.lo), vcltq_u8(v8, r.lo)),
                          vorrq_u8(vcltq_u8(v4, r.lo), vcltq_u8(v12, r.lo)));
  return r;
}

}  // namespace ale::features::internal

#endif
