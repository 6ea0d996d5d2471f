// NEON 7x7 Gaussian, bit-exact with blur_ref.cpp: 16 pixels per step, u8 x u8 -> u16 multiply-
// accumulate (the sum is at most 255 * 256), one rounding narrow. Row ends are covered by one
// more, overlapping step (it rewrites pixels with the values they already have), so no scalar tail
// unless the row is shorter than a vector.
#include "core/features/blur.h"

#if defined(__ARM_NEON)
#include <arm_neon.h>
#endif

namespace ale::features::internal {

#if defined(__ARM_NEON)

namespace {

inline uint8x16_t taps7(const uint8x16_t v[7]) {
  const uint8x8_t w0 = vdup_n_u8(kBlurTaps[0]), w1 = vdup_n_u8(kBlurTaps[1]), w2 = vdup_n_u8(kBlurTaps[2]),
                  w3 = vdup_n_u8(kBlurTaps[3]);
  uint16x8_t lo = vmull_u8(vget_low_u8(v[3]), w3);
  uint16x8_t hi = vmull_u8(vget_high_u8(v[3]), w3);
  lo = vmlal_u8(lo, vget_low_u8(v[0]), w0);
  hi = vmlal_u8(hi, vget_high_u8(v[0]), w0);
  lo = vmlal_u8(lo, vget_low_u8(v[6]), w0);
  hi = vmlal_u8(hi, vget_high_u8(v[6]), w0);
  lo = vmlal_u8(lo, vget_low_u8(v[1]), w1);
  hi = vmlal_u8(hi, vget_high_u8(v[1]), w1);
  lo = vmlal_u8(lo, vget_low_u8(v[5]), w1);
  hi = vmlal_u8(hi, vget_high_u8(v[5]), w1);
  lo = vmlal_u8(lo, vget_low_u8(v[2]), w2);
  hi = vmlal_u8(hi, vget_high_u8(v[2]), w2);
  lo = vmlal_u8(lo, vget_low_u8(v[4]), w2);
  hi = vmlal_u8(hi, vget_high_u8(v[4]), w2);
  return vcombine_u8(vrshrn_n_u16(lo, 8), vrshrn_n_u16(hi, 8));
}

}  // namespace

void blur_vertical_neon(GrayView src, int y, std::uint8_t* vrow) {
  const int w = src.width;
  if (w < 16) {
    blur_vertical_ref(src, y, vrow);
    return;
  }
  const std::uint8_t* r[7];
  for (int k = 0; k < 7; ++k) r[k] = src.row(y + k - kBlurRadius);
  for (int x = 0;; x += 16) {
    if (x > w - 16) x = w - 16;
    uint8x16_t v[7];
    for (int k = 0; k < 7; ++k) v[k] = vld1q_u8(r[k] + x);
    vst1q_u8(vrow + x, taps7(v));
    if (x == w - 16) break;
  }
}

void blur_horizontal_neon(const std::uint8_t* vrow, int width, std::uint8_t* out) {
  const int x_end = width - kBlurRadius;
  if (x_end - kBlurRadius < 16) {
    blur_horizontal_ref(vrow, width, out);
    return;
  }
  for (int x = kBlurRadius;; x += 16) {
    if (x > x_end - 16) x = x_end - 16;
    uint8x16_t v[7];
    for (int k = 0; k < 7; ++k) v[k] = vld1q_u8(vrow + x + k - kBlurRadius);
    vst1q_u8(out + x, taps7(v));
    if (x == x_end - 16) break;
  }
}

#else

void blur_vertical_neon(GrayView src, int y, std::uint8_t* vrow) { blur_vertical_ref(src, y, vrow); }
void blur_horizontal_neon(const std::uint8_t* vrow, int width, std::uint8_t* out) {
  blur_horizontal_ref(vrow, width, out);
}

#endif

}  // namespace ale::features::internal
