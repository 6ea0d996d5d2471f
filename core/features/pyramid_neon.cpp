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

inline Row16 horizontal16(const std::uint8_t* window, const ResizeBlock& block, uint8x8_t round) {
  const uint8x8x4_t win = vld4_u8(window);
  const uint8x8x4_t idx = vld4_u8(block.idx);
  const uint8x8x4_t wts = vld4_u8(block.wts);
  const uint8x8_t a_even = vtbl4_u8(win, idx.val[0]);
  const uint8x8_t a_odd = vtbl4_u8(win, idx.val[1]);
  const uint8x8_t b_even = vtbl4_u8(win, idx.val[2]);
  const uint8x8_t b_odd = vtbl4_u8(win, idx.val[3]);
  return {vmlal_u8(vmlal_u8(vaddl_u8(a_even, round), a_even, wts.val[2]), b_even, wts.val[0]),
          vmlal_u8(vmlal_u8(vaddl_u8(a_odd, round), a_odd, wts.val[3]), b_odd, wts.val[1])};
}

// vmull_n would move the scalar into a lane before every multiply (GCC 12), hence vector weights.
inline uint8x16_t vertical16(Row16 a, Row16 b, uint16x4_t w0, uint16x4_t w1) {
  const uint32x4_t s0 = vmlal_u16(vmull_u16(vget_low_u16(a.even), w0), vget_low_u16(b.even), w1);
  const uint32x4_t s1 = vmlal_u16(vmull_u16(vget_high_u16(a.even), w0), vget_high_u16(b.even), w1);
  const uint32x4_t s2 = vmlal_u16(vmull_u16(vget_low_u16(a.odd), w0), vget_low_u16(b.odd), w1);
  const uint32x4_t s3 = vmlal_u16(vmull_u16(vget_high_u16(a.odd), w0), vget_high_u16(b.odd), w1);
  // Little-endian: the odd 16-bit halves are the high ones, i.e. the outputs (below 256).
  const uint16x8_t even = vuzpq_u16(vreinterpretq_u16_u32(s0), vreinterpretq_u16_u32(s1)).val[1];
  const uint16x8_t odd = vuzpq_u16(vreinterpretq_u16_u32(s2), vreinterpretq_u16_u32(s3)).val[1];
  return vreinterpretq_u8_u16(vsliq_n_u16(even, odd, 8));
}

// One instruction each way (two vld1/vst1 cost pointer copies, GCC 12); the interleaved order in
// memory does not matter, only that it round-trips.
inline Row16 load16(const std::uint16_t* h) {
  const uint16x8x2_t r = vld2q_u16(h);
  return {r.val[0], r.val[1]};
}

inline void store16(std::uint16_t* h, Row16 r) { vst2q_u16(h, uint16x8x2_t{{r.even, r.odd}}); }

// Horizontal pass of source row `src` into `h`.
void horizontal_row(const std::uint8_t* src, const ResizePlan& plan, std::uint16_t* h) {
  const uint8x8_t round = vdup_n_u8(128);
  const std::uint8_t* window = src + plan.blocks.front().base;
  for (const ResizeBlock& block : plan.blocks) {
    store16(h, horizontal16(window, block, round));
    window += block.step;
    h += 16;
  }
}

// One block of an output row from rows h0 and h1 (wy on h1); kMake: h1 is made here from the
// source window and stored (one pass instead of a store and a reload).
template <bool kMake>
inline uint8x16_t output16(const std::uint16_t* h0, std::uint16_t* h1, const std::uint8_t* window,
                           const ResizeBlock& block, uint8x8_t round, uint16x4_t w0, uint16x4_t w1) {
  Row16 b;
  if constexpr (kMake) {
    b = horizontal16(window, block, round);
    store16(h1, b);
  } else {
    b = load16(h1);
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
    h0 += 16;
    h1 += 16;
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
