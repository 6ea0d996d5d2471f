// NEON bilinear downscale, bit-exact with pyramid_ref.cpp, horizontal pass first (pyramid.h says
// why that is the same arithmetic). Per source row and 16 outputs: one vld4 of the 32-pixel
// window, vtbl4 gathers of both samples with the plan's permuted indices (even outputs in one
// vector, odd ones in the other), and h = a + 128 + a (255 - w) + b w (= a (256 - w) + b w + 128,
// at most 65408, so 16 bits; 256 - w does not fit a byte). Per output row: h0 (256 - wy) + h1 wy
// in 32 bits, whose byte 2 is the output (the +128 of both rows is the 32768 of the rounding):
// two vuzp take the high halves and one vsli puts the odd outputs between the even ones. Each
// source row is resampled in the same loop as the output row that first needs it, so its 16-bit
// samples go straight from the horizontal to the vertical pass; consecutive output rows on source
// rows c, c + 1 and c + 1, c + 2 go in one pass (row c + 1 is never stored). One 16-bit row (with one
// 16-sample slot per block, so the last, overlapping block does not overwrite its neighbour) holds
// the newest source row for the next output row.
// Cost on ARM per 16 outputs: 33 instructions and row in a pair, 38 alone (3 vld4, 4 vtbl and 6
// multiply-adds per new source row, 2 q loads and stores of the held row, 8 multiplies, 2 vuzp,
// 1 vsli, 1 store per output row).
#include "core/features/pyramid.h"

#if defined(__ARM_NEON)
#include <arm_neon.h>

namespace ale::features::internal {

namespace {

// A block's 16 outputs as two 16-bit vectors: the even outputs and the odd ones (the plan's lane
// order). They travel as separate q registers, not as a struct: GCC 12 moved such a struct
// through the stack between the inline assembly statements below (8 vstr/vldr per block).

// Both samples of the 16 outputs from the window, and the block's weights.
struct Samples {
  uint8x8_t a_even, a_odd, b_even, b_odd;
  uint8x8x4_t wts;
};

inline Samples gather(const std::uint8_t* window, const ResizeBlock& block) {
  const uint8x8x4_t win = vld4_u8(window);
  const uint8x8x4_t idx = vld4_u8(block.idx);
  return {vtbl4_u8(win, idx.val[0]), vtbl4_u8(win, idx.val[1]), vtbl4_u8(win, idx.val[2]), vtbl4_u8(win, idx.val[3]),
          vld4_u8(block.wts)};
}

// The arithmetic is in inline assembly (AArch32 only): with intrinsics GCC 12 copied the
// multiply-accumulate chains and the vst2/vld2 register pairs between q registers, 6 vorr per 16
// outputs. The 16-bit rows go as two q stores and loads: the interleaved order in memory does not
// matter, only that it round-trips, and single q registers need no pairing.
#if defined(__arm__)
// h = a (256 - w) + b w + 128 for the block's even (e) and odd (o) outputs.
inline void horizontal16(const std::uint8_t* window, const ResizeBlock& block, uint8x8_t round, uint16x8_t& e,
                         uint16x8_t& o) {
  const Samples g = gather(window, block);
  asm("vaddl.u8 %q[e], %P[ae], %P[rd]\n\t"
      "vaddl.u8 %q[o], %P[ao], %P[rd]\n\t"
      "vmlal.u8 %q[e], %P[ae], %P[ve]\n\t"
      "vmlal.u8 %q[o], %P[ao], %P[vo]\n\t"
      "vmlal.u8 %q[e], %P[be], %P[we]\n\t"
      "vmlal.u8 %q[o], %P[bo], %P[wo]"
      : [e] "=&w"(e), [o] "=&w"(o)
      : [ae] "w"(g.a_even), [ao] "w"(g.a_odd), [be] "w"(g.b_even), [bo] "w"(g.b_odd), [rd] "w"(round),
        [we] "w"(g.wts.val[0]), [wo] "w"(g.wts.val[1]), [ve] "w"(g.wts.val[2]), [vo] "w"(g.wts.val[3]));
}

// Outputs from rows a (weight w0) and b (w1): the 32-bit sums' byte 2. Little-endian: the odd
// 16-bit halves of the sums are the high ones, i.e. the outputs (below 256); two vuzp gather them
// and one vsli puts the odd outputs between the even ones.
inline uint8x16_t vertical16(uint16x8_t ae, uint16x8_t ao, uint16x8_t be, uint16x8_t bo, uint16x4_t w0,
                             uint16x4_t w1) {
  uint32x4_t s0, s1, s2, s3;
  asm("vmull.u16 %q[s0], %e[ae], %P[w0]\n\t"
      "vmull.u16 %q[s1], %f[ae], %P[w0]\n\t"
      "vmull.u16 %q[s2], %e[ao], %P[w0]\n\t"
      "vmull.u16 %q[s3], %f[ao], %P[w0]\n\t"
      "vmlal.u16 %q[s0], %e[be], %P[w1]\n\t"
      "vmlal.u16 %q[s1], %f[be], %P[w1]\n\t"
      "vmlal.u16 %q[s2], %e[bo], %P[w1]\n\t"
      "vmlal.u16 %q[s3], %f[bo], %P[w1]\n\t"
      "vuzp.16 %q[s0], %q[s1]\n\t"
      "vuzp.16 %q[s2], %q[s3]\n\t"
      "vsli.16 %q[s1], %q[s3], #8"
      : [s0] "=&w"(s0), [s1] "=&w"(s1), [s2] "=&w"(s2), [s3] "=&w"(s3)
      : [ae] "w"(ae), [ao] "w"(ao), [be] "w"(be), [bo] "w"(bo), [w0] "w"(w0), [w1] "w"(w1));
  return vreinterpretq_u8_u32(s1);
}

inline void load16(const std::uint16_t*& h, uint16x8_t& e, uint16x8_t& o) {
  asm("vld1.16 {%q0}, [%2]!\n\tvld1.16 {%q1}, [%2]!"
      : "=w"(e), "=w"(o), "+r"(h)
      : "m"(*reinterpret_cast<const std::uint16_t(*)[16]>(h)));
}

inline void store16(std::uint16_t*& h, uint16x8_t e, uint16x8_t o) {
  asm("vst1.16 {%q2}, [%1]!\n\tvst1.16 {%q3}, [%1]!"
      : "=m"(*reinterpret_cast<std::uint16_t(*)[16]>(h)), "+r"(h)
      : "w"(e), "w"(o));
}
#else
inline void horizontal16(const std::uint8_t* window, const ResizeBlock& block, uint8x8_t round, uint16x8_t& e,
                         uint16x8_t& o) {
  const Samples g = gather(window, block);
  e = vmlal_u8(vmlal_u8(vaddl_u8(g.a_even, round), g.a_even, g.wts.val[2]), g.b_even, g.wts.val[0]);
  o = vmlal_u8(vmlal_u8(vaddl_u8(g.a_odd, round), g.a_odd, g.wts.val[3]), g.b_odd, g.wts.val[1]);
}

inline uint8x16_t vertical16(uint16x8_t ae, uint16x8_t ao, uint16x8_t be, uint16x8_t bo, uint16x4_t w0,
                             uint16x4_t w1) {
  const uint32x4_t s0 = vmlal_u16(vmull_u16(vget_low_u16(ae), w0), vget_low_u16(be), w1);
  const uint32x4_t s1 = vmlal_u16(vmull_u16(vget_high_u16(ae), w0), vget_high_u16(be), w1);
  const uint32x4_t s2 = vmlal_u16(vmull_u16(vget_low_u16(ao), w0), vget_low_u16(bo), w1);
  const uint32x4_t s3 = vmlal_u16(vmull_u16(vget_high_u16(ao), w0), vget_high_u16(bo), w1);
  const uint16x8_t even = vuzpq_u16(vreinterpretq_u16_u32(s0), vreinterpretq_u16_u32(s1)).val[1];
  const uint16x8_t odd = vuzpq_u16(vreinterpretq_u16_u32(s2), vreinterpretq_u16_u32(s3)).val[1];
  return vreinterpretq_u8_u16(vsliq_n_u16(even, odd, 8));
}

inline void load16(const std::uint16_t*& h, uint16x8_t& e, uint16x8_t& o) {
  e = vld1q_u16(h);
  o = vld1q_u16(h + 8);
  h += 16;
}

inline void store16(std::uint16_t*& h, uint16x8_t e, uint16x8_t o) {
  vst1q_u16(h, e);
  vst1q_u16(h + 8, o);
  h += 16;
}
#endif

// Horizontal pass of source row `src` into `h`.
void horizontal_row(const std::uint8_t* src, const ResizePlan& plan, std::uint16_t* h) {
  const uint8x8_t round = vdup_n_u8(128);
  const std::uint8_t* window = src + plan.blocks.front().base;
  for (const ResizeBlock& block : plan.blocks) {
    uint16x8_t e, o;
    horizontal16(window, block, round, e, o);
    store16(h, e, o);
    window += block.step;
  }
}

// Vertical weights of an output row: 256 - wy on the upper source row, wy on the lower.
struct RowWeights {
  uint16x4_t w0, w1;
  explicit RowWeights(int wy)
      : w0(vdup_n_u16(static_cast<std::uint16_t>(256 - wy))), w1(vdup_n_u16(static_cast<std::uint16_t>(wy))) {}
};

// The 16 outputs of `block` from source rows c (16-bit row `h`, made before) and c + 1 (8-bit
// `window`, resampled here and stored over row c in `h`), weights w.
inline uint8x16_t output16(std::uint16_t*& h, const std::uint8_t* window, const ResizeBlock& block, uint8x8_t round,
                           const RowWeights& w) {
  uint16x8_t ae, ao, be, bo;
  horizontal16(window, block, round, be, bo);
  const std::uint16_t* in = h;
  load16(in, ae, ao);  // before the store below overwrites it
  store16(h, be, bo);
  return vertical16(ae, ao, be, bo, w.w0, w.w1);
}

// Output row `out` from source rows c (16-bit row `h`) and c + 1 (`src1`); h then holds row c + 1.
void output_row(std::uint16_t* h, const std::uint8_t* src1, int wy, const ResizePlan& plan, std::uint8_t* out) {
  const uint8x8_t round = vdup_n_u8(128);
  const RowWeights w(wy);
  const std::uint8_t* window = src1 + plan.blocks.front().base;
  std::uint8_t* const out_last = out + plan.dst_w - 16;
  const ResizeBlock* block = plan.blocks.data();
  const ResizeBlock* last = block + plan.blocks.size() - 1;
  for (; block != last; ++block) {
    vst1q_u8(out, output16(h, window, *block, round, w));
    window += block->step;
    out += 16;
  }
  vst1q_u8(out_last, output16(h, window, *block, round, w));
}

// Two consecutive output rows from source rows c, c + 1 (wy) and c + 1, c + 2 (wy2) in one pass:
// row c + 1 is resampled and used at once, never stored; h (row c) then holds row c + 2.
void output_pair(std::uint16_t* h, const std::uint8_t* src1, int stride, int wy, int wy2, const ResizePlan& plan,
                 std::uint8_t* out, std::uint8_t* out2) {
  const uint8x8_t round = vdup_n_u8(128);
  const RowWeights w(wy), v(wy2);
  const std::uint8_t* window = src1 + plan.blocks.front().base;
  const auto pair16 = [&](const ResizeBlock& block, std::uint8_t* o, std::uint8_t* o2) {
    uint16x8_t ae, ao, be, bo, ce, co;
    horizontal16(window, block, round, be, bo);
    const std::uint16_t* in = h;
    load16(in, ae, ao);
    vst1q_u8(o, vertical16(ae, ao, be, bo, w.w0, w.w1));
    horizontal16(window + stride, block, round, ce, co);
    store16(h, ce, co);
    vst1q_u8(o2, vertical16(be, bo, ce, co, v.w0, v.w1));
  };
  const ResizeBlock* block = plan.blocks.data();
  const ResizeBlock* last = block + plan.blocks.size() - 1;
  for (int x = 0; block != last; ++block, x += 16) {
    pair16(*block, out + x, out2 + x);
    window += block->step;
  }
  pair16(*block, out + plan.dst_w - 16, out2 + plan.dst_w - 16);
}

// Output row `out` from source row c alone (wy = 0), held in h.
void copy_row(const std::uint16_t* h, const ResizePlan& plan, std::uint8_t* out) {
  const RowWeights w(0);
  std::uint8_t* const out_last = out + plan.dst_w - 16;
  for (std::size_t k = 0; k < plan.blocks.size(); ++k) {
    uint16x8_t e, o;
    load16(h, e, o);
    vst1q_u8(k + 1 < plan.blocks.size() ? out + 16 * k : out_last, vertical16(e, o, e, o, w.w0, w.w1));
  }
}

}  // namespace

void resize_neon(GrayView src, MutableGrayView dst, const ResizePlan& plan, std::vector<std::uint16_t>& rows) {
  if (plan.blocks.empty()) {
    resize_ref(src, dst, plan, rows);
    return;
  }
  const std::size_t len = 16 * plan.blocks.size();
  if (rows.size() < len) rows.resize(len);
  // One 16-bit row: the source rows an output row reads only move down (dst is no larger than
  // src, so c0 increases from one output row to the next), so the newest row made is the only one
  // a later output row can share.
  std::uint16_t* const h = rows.data();
  int held = -1;
  for (int d = 0; d < plan.dst_h;) {
    const int c = plan.ys.c0[static_cast<std::size_t>(d)];
    const int wy = plan.ys.w[static_cast<std::size_t>(d)];
    if (held != c) horizontal_row(src.row(c), plan, h);
    held = c;
    if (wy == 0) {
      copy_row(h, plan, dst.row(d));
      ++d;
      continue;
    }
    if (d + 1 < plan.dst_h && plan.ys.c0[static_cast<std::size_t>(d + 1)] == c + 1 &&
        plan.ys.w[static_cast<std::size_t>(d + 1)] != 0) {
      output_pair(h, src.row(c + 1), src.stride, wy, plan.ys.w[static_cast<std::size_t>(d + 1)], plan, dst.row(d),
                  dst.row(d + 1));
      held = c + 2;
      d += 2;
    } else {
      output_row(h, src.row(c + 1), wy, plan, dst.row(d));
      held = c + 1;
      ++d;
    }
  }
}

}  // namespace ale::features::internal

#endif  // __ARM_NEON
