// ARM NEON FAST-9: 16 candidates per vector, identical corners and scores to fast9_row_ref().
//
// Why it is faster than the reference: the compass test (two neighbouring compass points beyond
// the threshold) rejects 16 pixels with 4 loads and a few compares; survivors get the full
// brighter/darker masks of all 16 circle pixels and a per-lane run counter over 24 positions
// (run = (run + 1) & mask, max kept), so "9 contiguous" is 3 vector operations per position. The
// score, needed only for the few corners, is fast9_score_neon() (one pixel, one vector per polarity,
// below). A row's last vector overlaps the one before (core/base/kernel_path.h); rows narrower
// than 16 pixels go to the reference.
#include "core/features/fast.h"

#include "core/features/fast_neon_common.h"

#if defined(__ARM_NEON)

namespace ale::features {

namespace internal {

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
  if (x_end - x_begin < 16) {  // narrower than a vector
    fast9_row_ref(image, y, x_begin, x_end, threshold, score_row, corners);
    return;
  }
  // The last vector ends at x_end, overlapping the one before: it rewrites the same scores, and
  // its corners are taken only from lanes >= first_new.
  int first_new = 0;
  for (int x = x_begin; x < x_end; first_new = 0, x += 16) {
    if (x + 16 > x_end) {
      first_new = x - (x_end - 16);
      x = x_end - 16;
    }
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
      const int s = fast9_score_neon(p + i, image.stride);
      score_row[x + i] = static_cast<std::uint8_t>(s);
      if (i >= first_new)
        corners.push_back(
            {static_cast<std::int16_t>(x + i), static_cast<std::int16_t>(y), static_cast<std::uint8_t>(s)});
    }
  }
}

namespace {

// Byte tables gathering the circle from 7 row loads of 8 bytes: rows -3..0 (32 bytes, one vtbl4)
// and rows 1..3 (24 bytes, one vtbx3 over what the first left as 0). Each row is loaded from
// x - 3, except row 3 from x - 4, so no load reads past (x + 3, y + 3): a 7x7 patch suffices.
struct CircleTables {
  std::uint8_t top[16];
  std::uint8_t bottom[16];
};

constexpr CircleTables make_circle_tables() {
  CircleTables t{};
  for (int k = 0; k < 16; ++k) {
    const int dx = internal::kCircleDx[k];
    const int dy = internal::kCircleDy[k];
    const int col = dx + (dy == 3 ? 4 : 3);
    t.top[k] = static_cast<std::uint8_t>(dy <= 0 ? (dy + 3) * 8 + col : 0xFF);
    t.bottom[k] = static_cast<std::uint8_t>(dy > 0 ? (dy - 1) * 8 + col : 0xFF);
  }
  return t;
}

constexpr CircleTables kCircleTables = make_circle_tables();

// The largest minimum over the 16 circular windows of 9 lanes: minima of 2, 4, 8 by doubling,
// then the 9th lane (8 on) joins.
inline uint8x16_t arc9_min(uint8x16_t v) {
  const uint8x16_t m2 = vminq_u8(v, vextq_u8(v, v, 1));
  const uint8x16_t m4 = vminq_u8(m2, vextq_u8(m2, m2, 2));
  const uint8x16_t m8 = vminq_u8(m4, vextq_u8(m4, m4, 4));
  return vminq_u8(m8, vextq_u8(v, v, 8));
}

}  // namespace

// The reference's d_k in u8 with saturation: a bright window's minimum of max(d_k, 0) is
// max(min d_k, 0), likewise for the dark one with -d_k, so the largest is max(best, 0) and a
// saturating - 1 gives the reference's max(best - 1, 0).
int fast9_score_neon(const std::uint8_t* p, int stride) {
  const std::uint8_t* r = p - 3 * stride - 3;
  uint8x8x4_t top;
  top.val[0] = vld1_u8(r);
  top.val[1] = vld1_u8(r + stride);
  top.val[2] = vld1_u8(r + 2 * stride);
  top.val[3] = vld1_u8(r + 3 * stride);
  uint8x8x3_t bottom;
  bottom.val[0] = vld1_u8(r + 4 * stride);
  bottom.val[1] = vld1_u8(r + 5 * stride);
  bottom.val[2] = vld1_u8(r + 6 * stride - 1);
  const uint8x16_t idx_top = vld1q_u8(kCircleTables.top);
  const uint8x16_t idx_bottom = vld1q_u8(kCircleTables.bottom);
  const uint8x8_t lo = vtbx3_u8(vtbl4_u8(top, vget_low_u8(idx_top)), bottom, vget_low_u8(idx_bottom));
  const uint8x8_t hi = vtbx3_u8(vtbl4_u8(top, vget_high_u8(idx_top)), bottom, vget_high_u8(idx_bottom));
  const uint8x16_t circle = vcombine_u8(lo, hi);
  const uint8x16_t centre = vld1q_dup_u8(p);
  const uint8x16_t best = vmaxq_u8(arc9_min(vqsubq_u8(circle, centre)), arc9_min(vqsubq_u8(centre, circle)));
  uint8x8_t m = vmax_u8(vget_low_u8(best), vget_high_u8(best));
  m = vpmax_u8(m, m);
  m = vpmax_u8(m, m);
  m = vpmax_u8(m, m);
  return vget_lane_u8(vqsub_u8(m, vdup_n_u8(1)), 0);
}

}  // namespace internal

}  // namespace ale::features

#endif  // __ARM_NEON
