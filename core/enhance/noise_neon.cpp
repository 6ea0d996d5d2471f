// NEON 3x3 binomial, bit-exact with binomial3_ref() (noise.h): per row the vertical sums
// above + 2 here + below of 16 pixels a step in 16-bit lanes, then the horizontal
// s[x-1] + 2 s[x] + s[x+1] of 8 a step, rounded and narrowed by one vrshrn (+8, >> 4; at most
// 16 * 255 = 4080, no overflow). Each pass's last step overlaps the one before it (a map: the
// overlapped outputs get the same values again, as the sums are not written by the second pass).
#include "core/enhance/noise.h"

#if defined(__ARM_NEON)
#include <arm_neon.h>

#include <cstring>

namespace ale::enhance::internal {

void binomial3_neon(MutableGrayView img, std::uint8_t* rows, std::uint16_t* sums) {
  const int w = img.width, h = img.height;
  if (w < 16) {
    binomial3_ref(img, rows, sums);
    return;
  }
  const std::size_t n = static_cast<std::size_t>(w);
  std::uint8_t* above = rows;  // the original of the row above (rows are filtered in place)
  std::uint8_t* here = rows + n;
  std::memcpy(above, img.row(0), n);
  const int last16 = w - 16;     // the overlapping last step of the vertical pass
  const int last8 = w - 1 - 8;   // and of the horizontal one, which writes [1, w - 1)
  for (int y = 1; y + 1 < h; ++y) {
    std::uint8_t* r = img.row(y);
    const std::uint8_t* below = img.row(y + 1);
    std::memcpy(here, r, n);
    for (int x = 0;; x += 16) {
      if (x > last16) x = last16;
      const uint8x16_t a = vld1q_u8(above + x), b = vld1q_u8(here + x), c = vld1q_u8(below + x);
      const uint16x8_t lo = vaddq_u16(vaddl_u8(vget_low_u8(a), vget_low_u8(c)), vshll_n_u8(vget_low_u8(b), 1));
      const uint16x8_t hi = vaddq_u16(vaddl_u8(vget_high_u8(a), vget_high_u8(c)), vshll_n_u8(vget_high_u8(b), 1));
      vst1q_u16(sums + x, lo);
      vst1q_u16(sums + x + 8, hi);
      if (x == last16) break;
    }
    for (int x = 1;; x += 8) {
      if (x > last8) x = last8;
      const uint16x8_t s0 = vld1q_u16(sums + x - 1), s1 = vld1q_u16(sums + x), s2 = vld1q_u16(sums + x + 1);
      const uint16x8_t t = vaddq_u16(vaddq_u16(s0, s2), vshlq_n_u16(s1, 1));
      vst1_u8(r + x, vrshrn_n_u16(t, 4));
      if (x == last8) break;
    }
    std::uint8_t* t = above;
    above = here;
    here = t;
  }
}

}  // namespace ale::enhance::internal

#endif  // __ARM_NEON
