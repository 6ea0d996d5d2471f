// ARM NEON FAST-9: 16 candidates per vector, identical corners and scores to fast9_row_ref().
//
// Why it is faster than the reference: the compass test (two neighbouring compass points beyond
// the threshold) rejects 16 pixels with 4 loads and a few compares; survivors get the full
// brighter/darker masks of all 16 circle pixels and a per-lane run counter over 24 positions
// (run = (run + 1) & mask, max kept), so "9 contiguous" is 3 vector operations per position. The
// score, needed only for the few corners, is the shared scalar fast9_score(). The tail of a row
// (fewer than 16 pixels) goes to the reference.
#include "core/features/fast.h"

#include "core/features/fast_neon_common.h"

namespace ale::features {

bool fast_neon_compiled() {
#if defined(__ARM_NEON)
  return true;
#else
  return false;
#endif
}

namespace internal {

#if defined(__ARM_NEON)

namespace {

// Lanes whose circular mask sequence m[0..15] holds 9 contiguous set lanes.
inline uint8x16_t arc9(const uint8x16_t m[16]) {
  const uint8x16_t one = vdupq_n_u8(1);
  uint8x16_t run = vdupq_n_u8(0);
  uint8x16_t longest = run;
  for (int k = 0; k < 24; ++k) {
    run = vandq_u8(vaddq_u8(run, one), m[k & 15]);
    longest = vmaxq_u8(longest, run);
  }
  return vcgeq_u8(longest, vdupq_n_u8(9));
}

}  // namespace

void fast9_row_neon(GrayView image, int y, int x_begin, int x_end, int threshold, std::uint8_t* score_row,
                    std::vector<FastCorner>& corners) {
  int off[16];
  fast9_offsets(image.stride, off);
  const std::uint8_t* row = image.row(y);
  const uint8x16_t t = vdupq_n_u8(static_cast<std::uint8_t>(threshold));
  const uint8x16_t zero = vdupq_n_u8(0);
  int x = x_begin;
  for (; x + 16 <= x_end; x += 16) {
    const std::uint8_t* p = row + x;
    const Compass cp = compass(p, image.stride, t);
    const uint8x16_t hi = cp.hi;
    const uint8x16_t lo = cp.lo;
    vst1q_u8(score_row + x, zero);
    const bool any_bright = any_lane(cp.maybe_bright);
    const bool any_dark = any_lane(cp.maybe_dark);
    if (!any_bright && !any_dark) continue;
    uint8x16_t v[16];
    for (int k = 0; k < 16; ++k) v[k] = vld1q_u8(p + off[k]);
    uint8x16_t is_corner = zero;
    uint8x16_t m[16];
    if (any_bright) {
      for (int k = 0; k < 16; ++k) m[k] = vcgtq_u8(v[k], hi);
      is_corner = arc9(m);
    }
    if (any_dark) {
      for (int k = 0; k < 16; ++k) m[k] = vcltq_u8(v[k], lo);
      is_corner = vorrq_u8(is_corner, arc9(m));
    }
    if (!any_lane(is_corner)) continue;
    alignas(16) std::uint8_t lanes[16];
    vst1q_u8(lanes, is_corner);
    for (int i = 0; i < 16; ++i) {
      if (lanes[i] == 0) continue;
      const int s = fast9_score(p + i, image.stride);
      score_row[x + i] = static_cast<std::uint8_t>(s);
      corners.push_back(
          {static_cast<std::int16_t>(x + i), static_cast<std::int16_t>(y), static_cast<std::uint8_t>(s)});
    }
  }
  if (x < x_end) fast9_row_ref(image, y, x, x_end, threshold, score_row, corners);
}

#else

void fast9_row_neon(GrayView image, int y, int x_begin, int x_end, int threshold, std::uint8_t* score_row,
                    std::vector<FastCorner>& corners) {
  fast9_row_ref(image, y, x_begin, x_end, threshold, score_row, corners);
}

#endif

}  // namespace internal
}  // namespace ale::features
