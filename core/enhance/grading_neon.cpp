// NEON moments of an image, bit-exact with moments_ref() (grading.h): the sums of the pixels and
// of their squares and the minimum, 16 pixels a step; a row's last step overlaps the previous one
// with those lanes masked out of the sums (the minimum takes them again, which does no harm).
// Rows narrower than 16 pixels, or wider than 2048, run the reference.
#include "core/enhance/grading.h"

#if defined(__ARM_NEON)
#include <arm_neon.h>

namespace ale::enhance::internal {

namespace {

// Lanes [16 - tail, 16) of a row's overlapping last step when w = 16 k + tail (all when tail = 0).
uint8x16_t tail_keep(int w) {
  static const std::uint8_t kLane[16] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15};
  const int tail = w % 16;
  return vcgeq_u8(vld1q_u8(kLane), vdupq_n_u8(static_cast<std::uint8_t>(tail == 0 ? 0 : 16 - tail)));
}

std::uint8_t lane_min(uint8x16_t v) {
  uint8x8_t m = vpmin_u8(vget_low_u8(v), vget_high_u8(v));
  m = vpmin_u8(m, m);
  m = vpmin_u8(m, m);
  m = vpmin_u8(m, m);
  return vget_lane_u8(m, 0);
}

}  // namespace

Moments moments_neon(GrayView image) {
  const int w = image.width > 0 ? image.width : 0;
  if (w < 16 || w > 2048) return moments_ref(image);
  std::uint64_t sum = 0, sum_sq = 0;
  // Byte sums in 16-bit lanes (at most 2 * 255 a step) folded into 32-bit lanes
  // before 128 steps, squares in 32-bit lanes (at most 4 * 65025 a step), both folded into the
  // 64-bit totals before 16,000 steps. Small images (the feature cells, 36-42 pixels wide) are
  // the common caller: per row only the loop and the overlapping step, no folding; the step is
  // in inline assembly on 32-bit ARM because GCC 12 adds three q-register copies to its 7
  // instructions.
  const int tail = w % 16;
  const uint8x16_t keep = tail_keep(w);
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
  for (int y = 0; y < image.height; ++y) {
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
  return moments_with_min(static_cast<std::uint64_t>(w) * static_cast<std::uint64_t>(image.height > 0 ? image.height : 0),
                          sum, sum_sq, lane_min(m8));
}

namespace {

// Sums of a cell's pixels and their squares in 32-bit lanes, and its minimum.
struct CellSums {
  uint32x4_t sum = vdupq_n_u32(0);
  uint32x4_t sum_sq = vdupq_n_u32(0);
  uint8x16_t low = vdupq_n_u8(255);
};

#if defined(__arm__)
// Rows of two full steps and a tail (cells 33-47 pixels wide, most of them) in inline assembly:
// loads that step to the next row by themselves and no inner loop, 25 instructions a row where
// GCC 12 gives 30 (copies of the loop-carried vectors).
void add_rows_2_tail(GrayView src, uint8x16_t keep, CellSums& c) {
  const std::uint8_t* p = src.data;
  const int to_tail = src.width - 32;             // after the second step
  const int to_next = src.stride - src.width + 16;  // after the tail
  int rows = src.height;
  uint8x16_t a, b, t;
  uint16x8_t s16, sq;
  asm volatile(
      "1:\n\t"
      "vld1.8 {%q[a]}, [%[p]]!\n\t"
      "vld1.8 {%q[b]}, [%[p]], %[to_tail]\n\t"
      "vld1.8 {%q[t]}, [%[p]], %[to_next]\n\t"
      "vmin.u8 %q[low], %q[low], %q[a]\n\t"
      "vmin.u8 %q[low], %q[low], %q[b]\n\t"
      "vmin.u8 %q[low], %q[low], %q[t]\n\t"
      "vand %q[t], %q[t], %q[keep]\n\t"
      "vpaddl.u8 %q[s16], %q[a]\n\t"
      "vpadal.u8 %q[s16], %q[b]\n\t"
      "vpadal.u8 %q[s16], %q[t]\n\t"
      "vmull.u8 %q[sq], %e[a], %e[a]\n\t"
      "vpadal.u16 %q[q32], %q[sq]\n\t"
      "vmull.u8 %q[sq], %f[a], %f[a]\n\t"
      "vpadal.u16 %q[q32], %q[sq]\n\t"
      "vmull.u8 %q[sq], %e[b], %e[b]\n\t"
      "vpadal.u16 %q[q32], %q[sq]\n\t"
      "vmull.u8 %q[sq], %f[b], %f[b]\n\t"
      "vpadal.u16 %q[q32], %q[sq]\n\t"
      "vmull.u8 %q[sq], %e[t], %e[t]\n\t"
      "vpadal.u16 %q[q32], %q[sq]\n\t"
      "vmull.u8 %q[sq], %f[t], %f[t]\n\t"
      "vpadal.u16 %q[q32], %q[sq]\n\t"
      "vpadal.u16 %q[s32], %q[s16]\n\t"
      "subs %[rows], %[rows], #1\n\t"
      "bne 1b\n\t"
      : [p] "+r"(p), [rows] "+r"(rows), [low] "+w"(c.low), [s32] "+w"(c.sum), [q32] "+w"(c.sum_sq), [a] "=&w"(a),
        [b] "=&w"(b), [t] "=&w"(t), [s16] "=&w"(s16), [sq] "=&w"(sq)
      : [to_tail] "r"(to_tail), [to_next] "r"(to_next), [keep] "w"(keep)
      : "cc", "memory");
}
#endif

// `full` 16-pixel steps a row and, with `tail`, a last step on the row's final 16 pixels, `keep`
// masking out of the sums the lanes the full steps saw.
void add_rows(GrayView src, int full, bool tail, uint8x16_t keep, CellSums& c) {
  const int w = src.width;
  for (int y = 0; y < src.height; ++y) {
    const std::uint8_t* p = src.row(y);
    uint16x8_t s16 = vdupq_n_u16(0);  // at most 2 * 255 a step, 128 steps a row
    for (int k = 0; k < full; ++k) {
      const uint8x16_t v = vld1q_u8(p + 16 * k);
      c.low = vminq_u8(c.low, v);
      s16 = vpadalq_u8(s16, v);
      c.sum_sq = vpadalq_u16(c.sum_sq, vmull_u8(vget_low_u8(v), vget_low_u8(v)));
      c.sum_sq = vpadalq_u16(c.sum_sq, vmull_u8(vget_high_u8(v), vget_high_u8(v)));
    }
    if (tail) {
      uint8x16_t v = vld1q_u8(p + w - 16);
      c.low = vminq_u8(c.low, v);  // the masked lanes were seen already
      v = vandq_u8(v, keep);
      s16 = vpadalq_u8(s16, v);
      c.sum_sq = vpadalq_u16(c.sum_sq, vmull_u8(vget_low_u8(v), vget_low_u8(v)));
      c.sum_sq = vpadalq_u16(c.sum_sq, vmull_u8(vget_high_u8(v), vget_high_u8(v)));
    }
    c.sum = vpadalq_u16(c.sum, s16);
  }
}

std::uint32_t lane_total(uint32x4_t v) {
  const uint32x2_t t = vpadd_u32(vget_low_u32(v), vget_high_u32(v));
  return vget_lane_u32(vpadd_u32(t, t), 0);
}

}  // namespace

Moments small_moments_neon(GrayView src) {
  // moments_neon() for images of any size pays per row for the folds that keep its sums exact; a
  // cell of at most 66,051 pixels (255^2 each) keeps every sum of squares below 2^32, so all sums
  // stay in 32-bit lanes to the end (and convert to double in one instruction), and rows of at
  // most 128 steps let the byte sums move from 16- to 32-bit lanes once a row: about half the
  // instructions on a 37 x 38 cell.
  const int w = src.width, h = src.height;
  if (w < 16 || w > 2048 || h < 1 || std::int64_t{w} * h > 66051) return moments_neon(src);
  const int tail = w % 16;
  const uint8x16_t keep = tail_keep(w);
  const int full = w / 16;
  CellSums c;
#if defined(__arm__)
  if (full == 2 && tail != 0)
    add_rows_2_tail(src, keep, c);
  else
#endif
    add_rows(src, full, tail != 0, keep, c);
  return moments_with_min(static_cast<std::uint32_t>(w * h), lane_total(c.sum), lane_total(c.sum_sq), lane_min(c.low));
}

}  // namespace ale::enhance::internal

#endif  // __ARM_NEON
