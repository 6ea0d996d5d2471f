// NEON FAST-9 score map, bit-exact with score_row_ref() (see score_map.h): 16 pixels per vector,
// sliding arc minimum (maximum) of the grey values by doubling, then one saturating difference
// with the centre per polarity. A row's last vector overlaps the previous
// one instead of falling back to scalar code (it rewrites the same scores; its corners are taken
// only from the lanes not seen yet); a segment narrower than 16 pixels is one vector with its extra lanes
// masked (moved left at the image's right edge), or the reference when the image is narrower than
// 22 pixels. A vector is scored only
// when, after the compass test, some lane has 4 consecutive even circle points past the threshold.
#include "core/features/score_map.h"

#include "core/features/fast_neon_common.h"

namespace ale::features::internal {

#if defined(__ARM_NEON)

namespace {

// Over the 16 arcs of 9 circle pixels: the largest arc minimum of the grey values (kBright) or the
// smallest arc maximum (kDark). A saturating difference with the centre is monotonic, so the
// brighter-arc score max_arc min_k (v_k - c) is (max_arc min_k v_k) - c, and the darker one
// c - (min_arc max_k v_k): the differences need not be formed per circle pixel.
enum class Polarity { kBright, kDark };

template <Polarity P>
inline uint8x16_t inner(uint8x16_t a, uint8x16_t b) {
  return P == Polarity::kBright ? vminq_u8(a, b) : vmaxq_u8(a, b);
}

template <Polarity P>
inline uint8x16_t arc_extreme(const uint8x16_t v[16]) {
  uint8x16_t m2[16], m4[16];
  for (int k = 0; k < 16; ++k) m2[k] = inner<P>(v[k], v[(k + 1) & 15]);
  for (int k = 0; k < 16; ++k) m4[k] = inner<P>(m2[k], m2[(k + 2) & 15]);
  uint8x16_t best = inner<P>(inner<P>(m4[0], m4[4]), v[8]);
  for (int k = 1; k < 16; ++k) {
    const uint8x16_t arc = inner<P>(inner<P>(m4[k], m4[(k + 4) & 15]), v[(k + 8) & 15]);
    best = P == Polarity::kBright ? vmaxq_u8(best, arc) : vminq_u8(best, arc);
  }
  return best;
}

// Bit i set when lane i is non-zero.
inline unsigned lane_mask(uint8x16_t v) {
  static const std::uint8_t kBits[16] = {1, 2, 4, 8, 16, 32, 64, 128, 1, 2, 4, 8, 16, 32, 64, 128};
  const uint8x16_t b = vandq_u8(vtstq_u8(v, v), vld1q_u8(kBits));
  uint8x8_t s = vpadd_u8(vget_low_u8(b), vget_high_u8(b));
  s = vpadd_u8(s, s);
  s = vpadd_u8(s, s);
  return vget_lane_u8(s, 0) | (static_cast<unsigned>(vget_lane_u8(s, 1)) << 8);
}

// Lanes where 4 consecutive even circle points (c0, c2, .., c14, cyclically) all pass (`pass[j]`
// for c_2j). Every arc of 9 holds 4 or 5 consecutive even points, so a lane outside this mask has
// no arc of that polarity; in noise (the retry cells) the compass test passes in nearly every
// vector and this one in far fewer, which saves scoring them.
inline uint8x16_t even_arc4(const uint8x16_t pass[8]) {
  uint8x16_t a2[8];
  for (int j = 0; j < 8; ++j) a2[j] = vandq_u8(pass[j], pass[(j + 1) & 7]);
  uint8x16_t any = vandq_u8(a2[0], a2[2]);
  for (int j = 1; j < 8; ++j) any = vorrq_u8(any, vandq_u8(a2[j], a2[(j + 2) & 7]));
  return any;
}

}  // namespace

void score_row_neon(GrayView image, int y, int x_begin, int x_end, int threshold, std::uint8_t* score_row,
                    std::vector<FastCorner>& corners) {
  // A segment narrower than a vector (the last cell of a row) is one vector whose extra lanes are
  // neither stored nor emitted; at the right edge of the image that vector ends at the last pixel
  // with a whole circle, and its lanes before the segment are masked as well.
  const int narrow = x_end - x_begin < 16 ? x_end - x_begin : 0;
  int first = x_begin;
  if (narrow != 0 && x_begin + 16 + kFastRadius > image.width) {
    first = image.width - kFastRadius - 16;
    if (first < kFastRadius) {
      score_row_ref(image, y, x_begin, x_end, threshold, score_row, corners);
      return;
    }
  }
  // A pass is about 30 rows of one stride: the circle offsets are worth keeping between rows.
  thread_local int off_stride = 0;
  thread_local int off[16];
  if (image.stride != off_stride) {
    fast9_offsets(image.stride, off);
    off_stride = image.stride;
  }
  const std::uint8_t* row = image.row(y);
  const uint8x16_t t = vdupq_n_u8(static_cast<std::uint8_t>(threshold));
  const uint8x16_t zero = vdupq_n_u8(0);
  int done = x_begin;  // lanes below this were emitted already
  for (int x = first;; x += 16) {
    if (narrow == 0 && x > x_end - 16) x = x_end - 16;
    const std::uint8_t* p = row + x;
    const Compass cp = compass(p, off, t);
    const uint8x16_t c = cp.c;
    bool any_bright = any_lane(cp.maybe_bright);
    bool any_dark = any_lane(cp.maybe_dark);
    uint8x16_t v[16];
    if (any_bright || any_dark) {
      for (int k = 0; k < 16; k += 2) v[k] = vld1q_u8(p + off[k]);
      uint8x16_t pass[8];
      if (any_bright) {
        for (int j = 0; j < 8; ++j) pass[j] = vcgtq_u8(v[2 * j], cp.hi);
        any_bright = any_lane(even_arc4(pass));
      }
      if (any_dark) {
        for (int j = 0; j < 8; ++j) pass[j] = vcltq_u8(v[2 * j], cp.lo);
        any_dark = any_lane(even_arc4(pass));
      }
    }
    uint8x16_t score = zero;
    if (any_bright || any_dark) {
      for (int k = 1; k < 16; k += 2) v[k] = vld1q_u8(p + off[k]);
      uint8x16_t best = zero;
      if (any_bright) best = vqsubq_u8(arc_extreme<Polarity::kBright>(v), c);
      if (any_dark) best = vmaxq_u8(best, vqsubq_u8(c, arc_extreme<Polarity::kDark>(v)));
      // score = best - 1 where best > t, else 0.
      score = vandq_u8(vsubq_u8(best, vdupq_n_u8(1)), vcgtq_u8(best, t));
    }
    if (narrow != 0) {
      static const std::uint8_t kLane[16] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15};
      const uint8x16_t lane = vld1q_u8(kLane);
      const uint8x16_t keep = vandq_u8(vcgeq_u8(lane, vdupq_n_u8(static_cast<std::uint8_t>(x_begin - x))),
                                       vcltq_u8(lane, vdupq_n_u8(static_cast<std::uint8_t>(x_end - x))));
      score = vandq_u8(score, keep);
      vst1q_u8(score_row + x, vbslq_u8(keep, score, vld1q_u8(score_row + x)));
    } else {
      vst1q_u8(score_row + x, score);
    }
    if (any_bright || any_dark) {
      unsigned mask = lane_mask(score);
      if (done > x) mask &= ~0u << (done - x);
      alignas(16) std::uint8_t lanes[16];
      if (mask != 0) {
        vst1q_u8(lanes, score);
        append_lane_corners(mask, lanes, x, y, corners);
      }
    }
    done = x + 16;
    if (narrow != 0 || x == x_end - 16) break;
  }
}

#else

void score_row_neon(GrayView image, int y, int x_begin, int x_end, int threshold, std::uint8_t* score_row,
                    std::vector<FastCorner>& corners) {
  score_row_ref(image, y, x_begin, x_end, threshold, score_row, corners);
}

#endif

}  // namespace ale::features::internal
