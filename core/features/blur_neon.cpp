// NEON 7x7 Gaussian, bit-exact with blur_ref.cpp: u8 x u8 -> u16 multiply-accumulate (a sum is at
// most 255 * 256) and one rounding narrow per pass.
//
// The rectangle is cut into bands of up to 8 rows and chunks of up to kChunk columns. Per band and
// chunk, the vertical pass walks each 16-column strip down the band (4 output rows from 10 loaded
// source rows, so 20 loads per 16 x 8 instead of 32 when rows go in pairs) into a small stack
// buffer, then the horizontal pass walks each 16-column step down the band (one 32-byte load per
// row, no per-row set-up) and takes the 7 shifted taps with vext. A remainder of up to 8 columns
// in either pass gets an 8-column step (the 6 columns the horizontal taps need past a whole number
// of 16-column strips, for one), a longer one an overlapping 16-column step that rewrites values
// already there, so no scalar tail unless the rectangle is narrower than a vector.
//
// Cost on ARM: per 16 columns, the vertical pass takes 78 instructions for 4 rows (10 loads, 56
// multiply-accumulates, 8 narrows, 4 stores) and the horizontal pass 24 per row (1 load, 6 vext,
// 14 multiply-accumulates, 2 narrows, 1 store), so about 3.3 per output pixel with the strips'
// tails and the per-rectangle set-up (rows in pairs took about a third more). 14
// multiply-accumulates per 8 outputs and pass
// is the floor for widening u8 multiplies: folding the symmetric taps, (a + g) * 18, needs one
// widening add per pair, as many instructions as the multiply-accumulate it saves.
#include "core/features/blur.h"

#include <algorithm>

#if defined(__ARM_NEON) && defined(__arm__)
#include <arm_neon.h>

namespace ale::features::internal {

namespace {

constexpr int kBandRows = 8;
constexpr int kChunk = 128;                       // output columns per band step
constexpr int kBufStride = kChunk + 32;           // the vertical pass writes chunk + 6, horizontal reads chunk + 19
constexpr int kTapOf[7] = {0, 1, 2, 3, 2, 1, 0};  // kBlurTaps[k] == taps[kTapOf[k]]

struct Taps {
  uint8x8_t w[4] = {vdup_n_u8(kBlurTaps[0]), vdup_n_u8(kBlurTaps[1]), vdup_n_u8(kBlurTaps[2]),
                    vdup_n_u8(kBlurTaps[3])};
};

// GCC turns pointer walks back into base + index addressing, which NEON loads and stores do not
// have (one add per access), so the walks are spelled out with post-incremented accesses.
inline uint8x16_t load_q_step(const std::uint8_t*& p, int step) {
  uint8x16_t v;
  asm("vld1.8 {%q0}, [%1], %2" : "=w"(v), "+r"(p) : "r"(step), "m"(*reinterpret_cast<const std::uint8_t(*)[16]>(p)));
  return v;
}

inline uint8x8_t load_d_step(const std::uint8_t*& p, int step) {
  uint8x8_t v;
  asm("vld1.8 {%P0}, [%1], %2" : "=w"(v), "+r"(p) : "r"(step), "m"(*reinterpret_cast<const std::uint8_t(*)[8]>(p)));
  return v;
}

inline void store_q_step(std::uint8_t*& p, uint8x16_t v, int step) {
  asm("vst1.8 {%q2}, [%1], %3" : "=m"(*reinterpret_cast<std::uint8_t(*)[16]>(p)), "+r"(p) : "w"(v), "r"(step));
}

inline void store_d_step(std::uint8_t*& p, uint8x8_t v, int step) {
  asm("vst1.8 {%P2}, [%1], %3" : "=m"(*reinterpret_cast<std::uint8_t(*)[8]>(p)), "+r"(p) : "w"(v), "r"(step));
}

struct AccQ {
  uint16x8_t lo, hi;
};

inline void mac(AccQ& a, uint8x16_t v, uint8x8_t w, bool first) {
  if (first) {
    a.lo = vmull_u8(vget_low_u8(v), w);
    a.hi = vmull_u8(vget_high_u8(v), w);
  } else {
    a.lo = vmlal_u8(a.lo, vget_low_u8(v), w);
    a.hi = vmlal_u8(a.hi, vget_high_u8(v), w);
  }
}

inline void mac(uint16x8_t& a, uint8x8_t v, uint8x8_t w, bool first) { a = first ? vmull_u8(v, w) : vmlal_u8(a, v, w); }

// Both halves narrowed straight into one q register (vcombine of two narrows costs GCC a move).
inline uint8x16_t rounded(const AccQ& a) {
  uint8x16_t r;
  asm("vrshrn.i16 %e0, %q1, #8\n\tvrshrn.i16 %f0, %q2, #8" : "=&w"(r) : "w"(a.lo), "w"(a.hi));
  return r;
}
inline uint8x8_t rounded(uint16x8_t a) { return vrshrn_n_u16(a, 8); }

inline void store_step(std::uint8_t*& p, uint8x16_t v, int step) { store_q_step(p, v, step); }
inline void store_step(std::uint8_t*& p, uint8x8_t v, int step) { store_d_step(p, v, step); }
inline uint8x16_t load_step(const std::uint8_t*& p, int step, AccQ) { return load_q_step(p, step); }
inline uint8x8_t load_step(const std::uint8_t*& p, int step, uint16x8_t) { return load_d_step(p, step); }

// Vertical pass of kRows consecutive rows over one strip (16 columns for Acc = AccQ, 8 for
// uint16x8_t): `in` points at the strip in source row y - 3 and ends kRows + 6 rows further down;
// `out` at the strip in buffer row 0 and ends kRows buffer rows further. Source row k feeds outputs
// k - 6 .. k, each finished as soon as its last row is in.
template <int kRows, typename Acc>
inline void vertical_strip(const std::uint8_t*& in, int stride, std::uint8_t*& out, const Taps& t) {
  Acc acc[kRows];
#pragma GCC unroll 16
  for (int k = 0; k < kRows + 2 * kBlurRadius; ++k) {
    const auto v = load_step(in, stride, Acc{});
#pragma GCC unroll 8
    for (int i = 0; i < kRows; ++i) {
      const int tap = k - i;
      if (tap < 0 || tap > 2 * kBlurRadius) continue;
      mac(acc[i], v, t.w[kTapOf[tap]], tap == 0);
      if (tap == 2 * kBlurRadius) store_step(out, rounded(acc[i]), kBufStride);
    }
  }
}

// The hot strips in inline assembly: with intrinsics GCC 12 copies accumulators between q registers
// (about one vorr per 5 multiply-accumulates here). Operands: a<i>l/a<i>h accumulate output row i
// (low/high 8 columns), v0/v1 take source rows in turn, n is the narrowed row, w0..w3 the taps.
#define ALE_LD(v) "vld1.8 {%q[" v "]}, [%[in]], %[s]\n\t"
#define ALE_MAC(op, a, v, w) \
  op " %q[" a "l], %e[" v "], %P[" w "]\n\t" op " %q[" a "h], %f[" v "], %P[" w "]\n\t"
#define ALE_MUL(a, v, w) ALE_MAC("vmull.u8", a, v, w)
#define ALE_MLA(a, v, w) ALE_MAC("vmlal.u8", a, v, w)
#define ALE_OUT(a) \
  "vrshrn.i16 %e[n], %q[" a "l], #8\n\tvrshrn.i16 %f[n], %q[" a "h], #8\n\tvst1.8 {%q[n]}, [%[out]], %[os]\n\t"

// vertical_strip<4, AccQ>: 10 loads, 56 multiply-accumulates, 8 narrows, 4 stores.
template <>
inline void vertical_strip<4, AccQ>(const std::uint8_t*& in, int stride, std::uint8_t*& out, const Taps& t) {
  uint16x8_t a0l, a0h, a1l, a1h, a2l, a2h, a3l, a3h;
  uint8x16_t v0, v1, n;
  asm volatile(
      ALE_LD("v0") ALE_MUL("a0", "v0", "w0")
      ALE_LD("v1") ALE_MLA("a0", "v1", "w1") ALE_MUL("a1", "v1", "w0")
      ALE_LD("v0") ALE_MLA("a0", "v0", "w2") ALE_MLA("a1", "v0", "w1") ALE_MUL("a2", "v0", "w0")
      ALE_LD("v1") ALE_MLA("a0", "v1", "w3") ALE_MLA("a1", "v1", "w2") ALE_MLA("a2", "v1", "w1")
                   ALE_MUL("a3", "v1", "w0")
      ALE_LD("v0") ALE_MLA("a0", "v0", "w2") ALE_MLA("a1", "v0", "w3") ALE_MLA("a2", "v0", "w2")
                   ALE_MLA("a3", "v0", "w1")
      ALE_LD("v1") ALE_MLA("a0", "v1", "w1") ALE_MLA("a1", "v1", "w2") ALE_MLA("a2", "v1", "w3")
                   ALE_MLA("a3", "v1", "w2")
      ALE_LD("v0") ALE_MLA("a0", "v0", "w0") ALE_OUT("a0") ALE_MLA("a1", "v0", "w1") ALE_MLA("a2", "v0", "w2")
                   ALE_MLA("a3", "v0", "w3")
      ALE_LD("v1") ALE_MLA("a1", "v1", "w0") ALE_OUT("a1") ALE_MLA("a2", "v1", "w1") ALE_MLA("a3", "v1", "w2")
      ALE_LD("v0") ALE_MLA("a2", "v0", "w0") ALE_OUT("a2") ALE_MLA("a3", "v0", "w1")
      ALE_LD("v1") ALE_MLA("a3", "v1", "w0") ALE_OUT("a3")
      : [in] "+r"(in), [out] "+r"(out), [a0l] "=&w"(a0l), [a0h] "=&w"(a0h), [a1l] "=&w"(a1l), [a1h] "=&w"(a1h),
        [a2l] "=&w"(a2l), [a2h] "=&w"(a2h), [a3l] "=&w"(a3l), [a3h] "=&w"(a3h), [v0] "=&w"(v0), [v1] "=&w"(v1),
        [n] "=&w"(n)
      : [s] "r"(stride), [os] "r"(kBufStride), [w0] "w"(t.w[0]), [w1] "w"(t.w[1]), [w2] "w"(t.w[2]),
        [w3] "w"(t.w[3])
      : "memory");
}

#undef ALE_OUT
#undef ALE_MLA
#undef ALE_MUL
#undef ALE_MAC
#undef ALE_LD

// Buffer rows 0 .. rows - 1, columns [0, n) (n >= 16) from source rows y - 3 .. y + rows + 2,
// columns [vx, vx + n).
void vertical_band(GrayView src, int y, int rows, int vx, int n, std::uint8_t* buf, const Taps& t) {
  const int stride = src.stride;
  const std::uint8_t* const top = src.row(y - kBlurRadius) + vx;
  // Each run of kRows output rows reads kRows + 6 source rows, and the next starts kRows below the
  // last one's start: step back 6 rows.
  const int back = 2 * kBlurRadius * stride;
  const auto strip = [&](int x, auto acc_tag) {
    using Acc = decltype(acc_tag);
    const std::uint8_t* in = top + x;
    std::uint8_t* out = buf + x;
    int r = rows;
    for (; r >= 4; r -= 4) {
      vertical_strip<4, Acc>(in, stride, out, t);
      in -= back;
    }
    for (; r > 0; --r) {
      vertical_strip<1, Acc>(in, stride, out, t);
      in -= back;
    }
  };
  const int whole = n / 16 * 16;
  for (int x = 0; x < whole; x += 16) strip(x, AccQ{});
  const int rest = n - whole;
  if (rest > 8)
    strip(n - 16, AccQ{});
  else if (rest > 0)
    strip(n - 8, uint16x8_t{});
}

// Output pixels x .. x + 15 from a = v[x - 3 .. x + 12] and b = v[x + 13 .. x + 28]: 6 vext,
// 14 multiply-accumulates, 2 narrows (in assembly for the reason above; e0/e1 take the shifted
// vectors in turn, the result goes to e0).
inline uint8x16_t horizontal16(uint8x16_t a, uint8x16_t b, const Taps& t) {
#define ALE_EXT(e, k) "vext.8 %q[" e "], %q[a], %q[b], #" k "\n\t"
#define ALE_MAC(op, v, w) op " %q[l], %e[" v "], %P[" w "]\n\t" op " %q[h], %f[" v "], %P[" w "]\n\t"
  uint8x16_t e0, e1;
  uint16x8_t l, h;
  asm(ALE_EXT("e0", "3") ALE_EXT("e1", "6") ALE_MAC("vmull.u8", "e0", "w3") ALE_MAC("vmlal.u8", "a", "w0")
      ALE_EXT("e0", "1") ALE_MAC("vmlal.u8", "e1", "w0")
      ALE_EXT("e1", "5") ALE_MAC("vmlal.u8", "e0", "w1")
      ALE_EXT("e0", "2") ALE_MAC("vmlal.u8", "e1", "w1")
      ALE_EXT("e1", "4") ALE_MAC("vmlal.u8", "e0", "w2") ALE_MAC("vmlal.u8", "e1", "w2")
      "vrshrn.i16 %e[e0], %q[l], #8\n\tvrshrn.i16 %f[e0], %q[h], #8"
      : [e0] "=&w"(e0), [e1] "=&w"(e1), [l] "=&w"(l), [h] "=&w"(h)
      : [a] "w"(a), [b] "w"(b), [w0] "w"(t.w[0]), [w1] "w"(t.w[1]), [w2] "w"(t.w[2]), [w3] "w"(t.w[3]));
#undef ALE_MAC
#undef ALE_EXT
  return e0;
}

// Output pixels x .. x + 7 from a = v[x - 3 .. x + 12].
inline uint8x8_t horizontal8(uint8x16_t a, const Taps& t) {
  const uint8x8_t lo = vget_low_u8(a), hi = vget_high_u8(a);
  uint16x8_t s = vmull_u8(vext_u8(lo, hi, 3), t.w[3]);
  s = vmlal_u8(s, lo, t.w[0]);
  s = vmlal_u8(s, vext_u8(lo, hi, 6), t.w[0]);
  s = vmlal_u8(s, vext_u8(lo, hi, 1), t.w[1]);
  s = vmlal_u8(s, vext_u8(lo, hi, 5), t.w[1]);
  s = vmlal_u8(s, vext_u8(lo, hi, 2), t.w[2]);
  s = vmlal_u8(s, vext_u8(lo, hi, 4), t.w[2]);
  return vrshrn_n_u16(s, 8);
}

// Output columns [x, x + 16) of `rows` rows from buffer columns [x, x + 32): one 32-byte load per
// row, walking down the buffer and the destination with post-incremented accesses.
inline void horizontal_column16(const std::uint8_t* in, std::uint8_t* out, int out_stride, int rows,
                                const Taps& t) {
  const auto one = [&] {
    uint8x16x2_t ab;
    asm("vld1.8 %h0, [%1], %2" : "=w"(ab), "+r"(in) : "r"(kBufStride), "m"(*reinterpret_cast<const std::uint8_t(*)[32]>(in)));
    store_q_step(out, horizontal16(ab.val[0], ab.val[1], t), out_stride);
  };
  if (rows == kBandRows) {
#pragma GCC unroll 8
    for (int i = 0; i < kBandRows; ++i) one();
  } else {
    for (int i = 0; i < rows; ++i) one();
  }
}

// The same for output columns [x, x + 8) from buffer columns [x, x + 16).
inline void horizontal_column8(const std::uint8_t* in, std::uint8_t* out, int out_stride, int rows, const Taps& t) {
  for (int i = 0; i < rows; ++i) store_d_step(out, horizontal8(load_q_step(in, kBufStride), t), out_stride);
}

// Output columns [0, n) (n >= 16) of `rows` rows from the buffer (buffer column k is the vertical
// pass at output column k - 3).
void horizontal_band(const std::uint8_t* buf, int rows, int n, std::uint8_t* out, int out_stride, const Taps& t) {
  const int whole = n / 16 * 16;
  for (int x = 0; x < whole; x += 16) horizontal_column16(buf + x, out + x, out_stride, rows, t);
  const int rest = n - whole;
  if (rest > 8)
    horizontal_column16(buf + n - 16, out + n - 16, out_stride, rows, t);
  else if (rest > 0)
    horizontal_column8(buf + n - 8, out + n - 8, out_stride, rows, t);
}

}  // namespace

void blur_rect_neon(GrayView src, MutableGrayView dst, PixelRect rect, std::uint8_t* scratch) {
  if (rect.width < 16) {
    blur_rect_ref(src, dst, rect, scratch);
    return;
  }
  const Taps t;
  alignas(16) std::uint8_t buf[kBandRows * kBufStride];
  const int x_end = rect.x + rect.width, y_end = rect.y + rect.height;
  for (int y = rect.y; y < y_end; y += kBandRows) {
    const int rows = std::min(kBandRows, y_end - y);
    for (int x = rect.x; x < x_end;) {
      // Chunks of kChunk columns, the last at least 16 wide.
      const int left = x_end - x;
      const int n = left <= kChunk ? left : left - kChunk >= 16 ? kChunk : left - 16;
      vertical_band(src, y, rows, x - kBlurRadius, n + 2 * kBlurRadius, buf, t);
      horizontal_band(buf, rows, n, dst.row(y) + x, dst.stride, t);
      x += n;
    }
  }
}

}  // namespace ale::features::internal

#endif  // __ARM_NEON && __arm__
