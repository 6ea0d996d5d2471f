// NEON bilinear downscale, bit-exact with pyramid_ref.cpp: the vertical pass 16 pixels per step
// (last step overlapping) into 16-bit samples, the horizontal pass 8 outputs per planned block,
// both samples of each output gathered bytewise with vtbl from the block's 16-sample window (the
// second sample of an output with weight 0 may be the padding after the row: it counts 0 times).
#include "core/features/pyramid.h"

#if defined(__ARM_NEON)
#include <arm_neon.h>
#endif

namespace ale::features::internal {

#if defined(__ARM_NEON)

void resize_vertical_neon(const std::uint8_t* r0, const std::uint8_t* r1, int width, int wy, std::uint16_t* out) {
  if (width < 16) {
    resize_vertical_ref(r0, r1, width, wy, out);
    return;
  }
  // a (256 - w) + b w = (a << 8) - a w + b w: 256 - w does not fit a byte when w = 0.
  const uint8x8_t w = vdup_n_u8(static_cast<std::uint8_t>(wy));
  for (int x = 0;; x += 16) {
    if (x > width - 16) x = width - 16;
    const uint8x16_t a = vld1q_u8(r0 + x);
    const uint8x16_t b = vld1q_u8(r1 + x);
    const uint8x8_t a_lo = vget_low_u8(a), a_hi = vget_high_u8(a);
    vst1q_u16(out + x, vmlal_u8(vmlsl_u8(vshll_n_u8(a_lo, 8), a_lo, w), vget_low_u8(b), w));
    vst1q_u16(out + x + 8, vmlal_u8(vmlsl_u8(vshll_n_u8(a_hi, 8), a_hi, w), vget_high_u8(b), w));
    if (x == width - 16) break;
  }
}

void resize_horizontal_neon(const std::uint16_t* row, const ResizePlan& plan, std::uint8_t* out) {
  if (plan.blocks.empty()) {
    resize_horizontal_ref(row, plan, out);
    return;
  }
  const uint8x16_t next = vdupq_n_u8(2);
  const uint16x8_t full = vdupq_n_u16(256);
  for (const ResizeBlock& b : plan.blocks) {
    const std::uint8_t* win = reinterpret_cast<const std::uint8_t*>(row + b.base);
    const uint8x16_t lo = vld1q_u8(win);
    const uint8x16_t hi = vld1q_u8(win + 16);
    const uint8x8x4_t tab = {{vget_low_u8(lo), vget_high_u8(lo), vget_low_u8(hi), vget_high_u8(hi)}};
    const uint8x16_t ia = vld1q_u8(b.bytes);
    const uint8x16_t ib = vaddq_u8(ia, next);
    const uint16x8_t a = vreinterpretq_u16_u8(vcombine_u8(vtbl4_u8(tab, vget_low_u8(ia)), vtbl4_u8(tab, vget_high_u8(ia))));
    const uint16x8_t c = vreinterpretq_u16_u8(vcombine_u8(vtbl4_u8(tab, vget_low_u8(ib)), vtbl4_u8(tab, vget_high_u8(ib))));
    const uint16x8_t w1 = vld1q_u16(b.w);
    const uint16x8_t w0 = vsubq_u16(full, w1);
    const uint32x4_t s_lo = vmlal_u16(vmull_u16(vget_low_u16(a), vget_low_u16(w0)), vget_low_u16(c), vget_low_u16(w1));
    const uint32x4_t s_hi =
        vmlal_u16(vmull_u16(vget_high_u16(a), vget_high_u16(w0)), vget_high_u16(c), vget_high_u16(w1));
    vst1_u8(out + b.x, vmovn_u16(vcombine_u16(vrshrn_n_u32(s_lo, 16), vrshrn_n_u32(s_hi, 16))));
  }
}

#else

void resize_vertical_neon(const std::uint8_t* r0, const std::uint8_t* r1, int width, int wy, std::uint16_t* out) {
  resize_vertical_ref(r0, r1, width, wy, out);
}
void resize_horizontal_neon(const std::uint16_t* row, const ResizePlan& plan, std::uint8_t* out) {
  resize_horizontal_ref(row, plan, out);
}

#endif

}  // namespace ale::features::internal
