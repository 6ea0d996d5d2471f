// NEON bilinear downscale, bit-exact with pyramid_ref.cpp, horizontal pass first (pyramid.h says
// why that is the same arithmetic). Per source row and 16 outputs: one vld4 of the 32-pixel
// window, vtbl4 gathers of both samples with the plan's permuted indices (even outputs in one
// vector, odd ones in the other), and h = a + 128 + a (255 - w) + b w (= a (256 - w) + b w + 128,
// at most 65408, so 16 bits; 256 - w does not fit a byte). Per output row: h0 (256 - wy) + h1 wy
// in 32 bits, whose byte 2 is the output (the +128 of both rows is the 32768 of the rounding):
// two vuzp take the high halves and one vsli puts the odd outputs between the even ones. The
// newest source row is resampled in the same loop as the output row that first needs it, so its
// 16-bit samples go straight from the horizontal to the vertical pass (and are stored for the
// next output row). The 16-bit rows keep one 16-sample slot per block, so the last, overlapping
// block does not overwrite its neighbour.
// Cost on ARM: 35 instructions per 16 outputs in the common step (one new source row: 3 vld4, 4
// vtbl, 6 multiply-adds, 2 q stores; the older row: 2 q loads; vertical: 8 multiplies, 2 vuzp, 1 vsli,
// 1 store; 6 scalar), about 1.72 M per 640x480 frame for levels 1..7 (632k outputs).
#include "core/features/pyramid.h"

#if defined(__ARM_NEON)
#include <arm_neon.h>
#endif

namespace ale::features::internal {

#if defined(__ARM_NEON)

namespace {

// Even outputs of one block in `even`, odd ones in `odd` (the plan's lane order), plus 128.
struct Row16 {
  uint16x8_t even, odd;
};

// Both samples of the 16 outputs of `block` from the window, and the block's weights.
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
inline Row16 horizontal16(const std::uint8_t* window, const ResizeBlock& block, uint8x8_t round) {
  const Samples g = gather(window, block);
  Row16 r;
  asm("vaddl.u8 %q[e], %P[ae], %P[rd]\n\t"
      "vaddl.u8 %q[o], %P[ao], %P[rd]\n\t"
      "vmlal.u8 %q[e], %P[ae], %P[ve]\n\t"
      "vmlal.u8 %q[o], %P[ao], %P[vo]\n\t"
      "vmlal.u8 %q[e], %P[be], %P[we]\n\t"
      "vmlal.u8 %q[o], %P[bo], %P[wo]"
      : [e] "=&w"(r.even), [o] "=&w"(r.odd)
      : [ae] "w"(g.a_even), [ao] "w"(g.a_odd), [be] "w"(g.b_even), [bo] "w"(g.b_odd), [rd] "w"(round),
        [we] "w"(g.wts.val[0]), [wo] "w"(g.wts.val[1]), [ve] "w"(g.wts.val[2]), [vo] "w"(g.wts.val[3]));
  return r;
}

inline uint8x16_t vertical16(Row16 a, Row16 b, uint16x4_t w0, uint16x4_t w1) {
  // Little-endian: the odd 16-bit halves of the 32-bit sums are the high ones, i.e. the outputs
  // (below 256); two vuzp gather them and one vsli puts the odd outputs between the even ones.
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
      : [ae] "w"(a.even), [ao] "w"(a.odd), [be] "w"(b.even), [bo] "w"(b.odd), [w0] "w"(w0), [w1] "w"(w1));
  return vreinterpretq_u8_u32(s1);
}

inline Row16 load16(const std::uint16_t*& h) {
  Row16 r;
  asm("vld1.16 {%q0}, [%2]!\n\tvld1.16 {%q1}, [%2]!"
      : "=w"(r.even), "=w"(r.odd), "+r"(h)
      : "m"(*reinterpret_cast<const std::uint16_t(*)[16]>(h)));
  return r;
}

inline void store16(std::uint16_t*& h, Row16 r) {
  asm("vst1.16 {%q2}, [%1]!\n\tvst1.16 {%q3}, [%1]!"
      : "=m"(*reinterpret_cast<std::uint16_t(*)[16]>(h)), "+r"(h)
      : "w"(r.even), "w"(r.odd));
}
#else
inline Row16 horizontal16(const std::uint8_t* window, const ResizeBlock& block, uint8x8_t round) {
  const Samples g = gather(window, block);
  return {vmlal_u8(vmlal_u8(vaddl_u8(g.a_even, round), g.a_even, g.wts.val[2]), g.b_even, g.wts.val[0]),
          vmlal_u8(vmlal_u8(vaddl_u8(g.a_odd, round), g.a_odd, g.wts.val[3]), g.b_odd, g.wts.val[1])};
}

inline uint8x16_t vertical16(Row16 a, Row16 b, uint16x4_t w0, uint16x4_t w1) {
  const uint32x4_t s0 = vmlal_u16(vmull_u16(vget_low_u16(a.even), w0), vget_low_u16(b.even), w1);
  const uint32x4_t s1 = vmlal_u16(vmull_u16(vget_high_u16(a.even), w0), vget_high_u16(b.even), w1);
  const uint32x4_t s2 = vmlal_u16(vmull_u16(vget_low_u16(a.odd), w0), vget_low_u16(b.odd), w1);
  const uint32x4_t s3 = vmlal_u16(vmull_u16(vget_high_u16(a.odd), w0), vget_high_u16(b.odd), w1);
  const uint16x8_t even = vuzpq_u16(vreinterpretq_u16_u32(s0), vreinterpretq_u16_u32(s1)).val[1];
  const uint16x8_t odd = vuzpq_u16(vreinterpretq_u16_u32(s2), vreinterpretq_u16_u32(s3)).val[1];
  return vreinterpretq_u8_u16(vsliq_n_u16(even, odd, 8));
}

inline Row16 load16(const std::uint16_t*& h) {
  const Row16 r{vld1q_u16(h), vld1q_u16(h + 8)};
  h += 16;
  return r;
}

inline void store16(std::uint16_t*& h, Row16 r) {
  vst1q_u16(h, r.even);
  vst1q_u16(h + 8, r.odd);
  h += 16;
}
#endif

// Horizontal pass of source row `src` into `h`.
void horizontal_row(const std::uint8_t* src, const ResizePlan& plan, std::uint16_t* h) {
  const uint8x8_t round = vdup_n_u8(128);
  const std::uint8_t* window = src + plan.blocks.front().base;
  for (const ResizeBlock& block : plan.blocks) {
    store16(h, horizontal16(window, block, round));
    window += block.step;
  }
}

// One block of an output row from rows h0 and h1 (wy on h1); kMake: h1 is made here from the
// source window and stored (one pass instead of a store and a reload). Both row pointers move on.
template <bool kMake>
inline uint8x16_t output16(const std::uint16_t*& h0, std::uint16_t*& h1, const std::uint8_t* window,
                           const ResizeBlock& block, uint8x8_t round, uint16x4_t w0, uint16x4_t w1) {
  Row16 b;
  if constexpr (kMake) {
    b = horizontal16(window, block, round);
    store16(h1, b);
  } else {
    const std::uint16_t* in = h1;
    b = load16(in);
    h1 += 16;
  }
  return vertical16(load16(h0), b, w0, w1);
}

// Output row `out`; kMake: h1 from source row src1 on the way.
template <bool kMake>
void output_row(const std::uint16_t* h0, std::uint16_t* h1, const std::uint8_t* src1, int wy, const ResizePlan& plan,
                std::uint8_t* out) {
  const uint8x8_t round = vdup_n_u8(128);
  const uint16x4_t w0 = vdup_n_u16(static_cast<std::uint16_t>(256 - wy));
  const uint16x4_t w1 = vdup_n_u16(static_cast<std::uint16_t>(wy));
  const std::uint8_t* window = src1 + plan.blocks.front().base;
  std::uint8_t* const out_last = out + plan.dst_w - 16;
  const ResizeBlock* block = plan.blocks.data();
  const ResizeBlock* last = block + plan.blocks.size() - 1;
  for (; block != last; ++block) {
    vst1q_u8(out, output16<kMake>(h0, h1, window, *block, round, w0, w1));
    if constexpr (kMake) window += block->step;
    out += 16;
  }
  vst1q_u8(out_last, output16<kMake>(h0, h1, window, *block, round, w0, w1));
}

}  // namespace

void resize_neon(GrayView src, MutableGrayView dst, const ResizePlan& plan, std::vector<std::uint16_t>& rows) {
  if (plan.blocks.empty()) {
    resize_bilinear(src, dst, plan, rows, FastPath::kReference);
    return;
  }
  const std::size_t len = 16 * plan.blocks.size();
  if (rows.size() < 2 * len) rows.resize(2 * len);
  std::uint16_t* slot[2] = {rows.data(), rows.data() + len};
  int held[2] = {-1, -1};
  for (int d = 0; d < plan.dst_h; ++d) {
    const int c = plan.ys.c0[static_cast<std::size_t>(d)];
    const int wy = plan.ys.w[static_cast<std::size_t>(d)];
    // Source rows only move down: the slot not holding c (or c + 1) holds a row no longer needed.
    int s0 = held[1] == c ? 1 : 0;
    if (held[s0] != c) {
      s0 = held[0] == c + 1 ? 1 : 0;
      horizontal_row(src.row(c), plan, slot[s0]);
      held[s0] = c;
    }
    if (wy == 0) {
      output_row<false>(slot[s0], slot[s0], src.row(c), 0, plan, dst.row(d));
      continue;
    }
    const int s1 = 1 - s0;
    if (held[s1] == c + 1)
      output_row<false>(slot[s0], slot[s1], src.row(c + 1), wy, plan, dst.row(d));
    else
      output_row<true>(slot[s0], slot[s1], src.row(c + 1), wy, plan, dst.row(d));
    held[s1] = c + 1;
  }
}

#else

void resize_neon(GrayView src, MutableGrayView dst, const ResizePlan& plan, std::vector<std::uint16_t>& rows) {
  resize_bilinear(src, dst, plan, rows, FastPath::kReference);
}

#endif

}  // namespace ale::features::internal
