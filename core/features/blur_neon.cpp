// NEON 7x7 Gaussian, bit-exact with blur_ref.cpp: u8 x u8 -> u16 multiply-accumulate (a sum is at
// most 255 * 256) and one rounding narrow per pass. Per pair of rows, the vertical pass reads the 8
// source rows once for both (4 loads per 16 pixels and row instead of 7) into two scratch rows;
// the horizontal pass loads each scratch vector once and takes the 7 shifted taps with vext. Row
// ends are covered by one more, overlapping step (it rewrites pixels with the values they already
// have), so no scalar tail unless the rectangle is narrower than a vector.
#include "core/features/blur.h"

#if defined(__ARM_NEON) && defined(__arm__)
#include <arm_neon.h>
#endif

namespace ale::features::internal {

#if defined(__ARM_NEON) && defined(__arm__)

namespace {

struct Taps {
  uint8x8_t w0 = vdup_n_u8(kBlurTaps[0]);
  uint8x8_t w1 = vdup_n_u8(kBlurTaps[1]);
  uint8x8_t w2 = vdup_n_u8(kBlurTaps[2]);
  uint8x8_t w3 = vdup_n_u8(kBlurTaps[3]);
};

struct Acc {
  uint16x8_t lo, hi;
};

inline Acc mul(uint8x16_t v, uint8x8_t w) { return {vmull_u8(vget_low_u8(v), w), vmull_u8(vget_high_u8(v), w)}; }

inline void mla(Acc& a, uint8x16_t v, uint8x8_t w) {
  a.lo = vmlal_u8(a.lo, vget_low_u8(v), w);
  a.hi = vmlal_u8(a.hi, vget_high_u8(v), w);
}

// GCC turns pointer walks back into base + index addressing, which NEON loads do not have (one
// add per load), so the walks are spelled out with post-incremented loads and stores.
inline uint8x16_t load_next(const std::uint8_t*& p) {
  uint8x16_t v;
  asm("vld1.8 {%q0}, [%1]!" : "=w"(v), "+r"(p) : "m"(*reinterpret_cast<const std::uint8_t(*)[16]>(p)));
  return v;
}

inline void store_next(std::uint8_t*& p, uint8x8_t v) {
  asm("vst1.8 {%P2}, [%1]!" : "=m"(*reinterpret_cast<std::uint8_t(*)[8]>(p)), "+r"(p) : "w"(v));
}

// The two halves are stored separately: vcombine of two narrows costs GCC a register move.
inline void store_rounded(std::uint8_t*& p, const Acc& a) {
  store_next(p, vrshrn_n_u16(a.lo, 8));
  store_next(p, vrshrn_n_u16(a.hi, 8));
}

// Vertical pass of rows y (into v0) and y + 1 (into v1) over 16 columns; r[k] points at row
// y - 3 + k. All pointers move on by 16 (post-incremented loads and stores).
inline void vertical2(const std::uint8_t* r[8], std::uint8_t*& v0, std::uint8_t*& v1, const Taps& t) {
  const auto next = load_next;
  uint8x16_t p = next(r[0]);
  Acc a = mul(p, t.w0);
  p = next(r[1]);
  mla(a, p, t.w1);
  Acc b = mul(p, t.w0);
  p = next(r[2]);
  mla(a, p, t.w2);
  mla(b, p, t.w1);
  p = next(r[3]);
  mla(a, p, t.w3);
  mla(b, p, t.w2);
  p = next(r[4]);
  mla(a, p, t.w2);
  mla(b, p, t.w3);
  p = next(r[5]);
  mla(a, p, t.w1);
  mla(b, p, t.w2);
  p = next(r[6]);
  mla(a, p, t.w0);
  mla(b, p, t.w1);
  p = next(r[7]);
  mla(b, p, t.w0);
  store_rounded(v0, a);
  store_rounded(v1, b);
}

// Row y alone (the last of an odd count).
inline void vertical1(const std::uint8_t* r[8], std::uint8_t*& v0, const Taps& t) {
  Acc a = mul(load_next(r[3]), t.w3);
  mla(a, load_next(r[0]), t.w0);
  mla(a, load_next(r[6]), t.w0);
  mla(a, load_next(r[1]), t.w1);
  mla(a, load_next(r[5]), t.w1);
  mla(a, load_next(r[2]), t.w2);
  mla(a, load_next(r[4]), t.w2);
  store_rounded(v0, a);
}

// Output pixels x .. x + 15 from a = v[x - 3 .. x + 12] and b = v[x + 13 .. x + 28].
inline void horizontal16(uint8x16_t a, uint8x16_t b, std::uint8_t*& out, const Taps& t) {
  Acc s = mul(vextq_u8(a, b, 3), t.w3);
  mla(s, a, t.w0);
  mla(s, vextq_u8(a, b, 6), t.w0);
  mla(s, vextq_u8(a, b, 1), t.w1);
  mla(s, vextq_u8(a, b, 5), t.w1);
  mla(s, vextq_u8(a, b, 2), t.w2);
  mla(s, vextq_u8(a, b, 4), t.w2);
  store_rounded(out, s);
}

// out[x0, x1) from v[x0 - 3, x1 + 3); x1 - x0 >= 16. Reads v up to x1 + 12 (lanes it ignores).
// Unrolled by two so the vector carried to the next step needs no register move.
inline void horizontal_row(const std::uint8_t* v, int x0, int x1, std::uint8_t* out, const Taps& t) {
  const std::uint8_t* in = v + x0 - kBlurRadius;
  std::uint8_t* o = out + x0;
  const int steps = (x1 - x0) / 16;
  uint8x16_t a = load_next(in);
  for (int n = steps / 2; n > 0; --n) {
    const uint8x16_t b = load_next(in);
    horizontal16(a, b, o, t);
    a = load_next(in);
    horizontal16(b, a, o, t);
  }
  if (steps % 2) horizontal16(a, load_next(in), o, t);
  if (steps * 16 != x1 - x0) {
    in = v + x1 - 16 - kBlurRadius;
    o = out + x1 - 16;
    const uint8x16_t c = load_next(in);
    horizontal16(c, load_next(in), o, t);
  }
}

}  // namespace

void blur_rect_neon(GrayView src, MutableGrayView dst, PixelRect rect, std::uint8_t* scratch) {
  if (rect.width < 16) {
    blur_rect_ref(src, dst, rect, scratch);
    return;
  }
  const Taps t;
  const int x0 = rect.x, x1 = rect.x + rect.width;
  const int vx0 = x0 - kBlurRadius, vx1 = x1 + kBlurRadius;
  std::uint8_t* v0 = scratch;
  std::uint8_t* v1 = scratch + src.width + 32;
  const int y_end = rect.y + rect.height;
  int y = rect.y;
  const int steps = (vx1 - vx0) / 16;
  const int last = vx1 - 16 - vx0;  // the overlapping step, when (vx1 - vx0) % 16 != 0
  for (; y + 2 <= y_end; y += 2) {
    const std::uint8_t* r[8];
    for (int k = 0; k < 8; ++k) r[k] = src.row(y + k - kBlurRadius) + vx0;
    std::uint8_t* o0 = v0 + vx0;
    std::uint8_t* o1 = v1 + vx0;
    for (int n = 0; n < steps; ++n) vertical2(r, o0, o1, t);
    if (steps * 16 != vx1 - vx0) {
      const int back = steps * 16 - last;
      for (auto& p : r) p -= back;
      o0 -= back;
      o1 -= back;
      vertical2(r, o0, o1, t);
    }
    horizontal_row(v0, x0, x1, dst.row(y), t);
    horizontal_row(v1, x0, x1, dst.row(y + 1), t);
  }
  if (y < y_end) {
    const std::uint8_t* r[8];
    for (int k = 0; k < 7; ++k) r[k] = src.row(y + k - kBlurRadius) + vx0;
    r[7] = r[6];
    std::uint8_t* o0 = v0 + vx0;
    for (int n = 0; n < steps; ++n) vertical1(r, o0, t);
    if (steps * 16 != vx1 - vx0) {
      const int back = steps * 16 - last;
      for (auto& p : r) p -= back;
      o0 -= back;
      vertical1(r, o0, t);
    }
    horizontal_row(v0, x0, x1, dst.row(y), t);
  }
}

#else

void blur_rect_neon(GrayView src, MutableGrayView dst, PixelRect rect, std::uint8_t* scratch) {
  blur_rect_ref(src, dst, rect, scratch);
}

#endif

}  // namespace ale::features::internal
