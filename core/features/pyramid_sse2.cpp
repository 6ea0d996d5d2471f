// SSE2 bilinear downscale, bit-exact with pyramid_ref.cpp (definition in pyramid.h).
// Vertical pass: r0 * 256 + (r1 - r0) * wy in 16-bit lanes, exact modulo 2^16 because the true
// value lies in 0..65280. Horizontal pass: each output's two 16-bit samples row[c0], row[c0 + 1]
// are one 32-bit load (SSE2 has no byte shuffle for a gather), and pmaddwd forms
// row[c0] * (256 - w) + row[c0 + 1] * w in 32 bits; pmaddwd is signed, so the samples are biased
// by -32768 and the bias (32768 * 256) added back with the rounding constant. With w = 0 the
// reference reads c0 only; here row[c0 + 1] (inside the row's 16 readable extra samples) is
// multiplied by 0. Row ends are covered by one more, overlapping step; shorter rows go to the
// reference.
#include <cstring>

#include "core/features/pyramid.h"

#include "core/features/sse2_common.h"

#if defined(__SSE2__)

namespace ale::features::internal {

namespace {

inline __m128i vertical8(__m128i a, __m128i b, __m128i wy) {
  return _mm_add_epi16(_mm_slli_epi16(a, 8), _mm_mullo_epi16(_mm_sub_epi16(b, a), wy));
}

inline int sample_pair(const std::uint16_t* row, std::int32_t c) {
  int v;
  std::memcpy(&v, row + c, 4);
  return v;
}

// 4 outputs from the pairs at row + c0[i] and weights w[i], as 32-bit lanes 0..255.
inline __m128i horizontal4(const std::uint16_t* row, const std::int32_t* c0, const std::uint8_t* w) {
  const __m128i p01 = _mm_unpacklo_epi32(_mm_cvtsi32_si128(sample_pair(row, c0[0])),
                                         _mm_cvtsi32_si128(sample_pair(row, c0[1])));
  const __m128i p23 = _mm_unpacklo_epi32(_mm_cvtsi32_si128(sample_pair(row, c0[2])),
                                         _mm_cvtsi32_si128(sample_pair(row, c0[3])));
  const __m128i pairs = _mm_xor_si128(_mm_unpacklo_epi64(p01, p23), _mm_set1_epi16(static_cast<short>(0x8000)));
  std::uint32_t w4;
  std::memcpy(&w4, w, 4);
  const __m128i wx = _mm_unpacklo_epi8(_mm_cvtsi32_si128(static_cast<int>(w4)), _mm_setzero_si128());
  const __m128i weights = _mm_unpacklo_epi16(_mm_sub_epi16(_mm_set1_epi16(256), wx), wx);
  const __m128i sum = _mm_add_epi32(_mm_madd_epi16(pairs, weights), _mm_set1_epi32(32768 * 256 + 32768));
  return _mm_srli_epi32(sum, 16);
}

}  // namespace

void resize_vertical_sse2(const std::uint8_t* r0, const std::uint8_t* r1, int width, int wy, std::uint16_t* out) {
  if (width < 16) {
    resize_vertical_ref(r0, r1, width, wy, out);
    return;
  }
  const __m128i zero = _mm_setzero_si128();
  const __m128i w = _mm_set1_epi16(static_cast<short>(wy));
  for (int x = 0;; x += 16) {
    if (x > width - 16) x = width - 16;
    const __m128i a = load16(r0 + x);
    const __m128i b = load16(r1 + x);
    __m128i* o = reinterpret_cast<__m128i*>(out + x);
    _mm_storeu_si128(o, vertical8(_mm_unpacklo_epi8(a, zero), _mm_unpacklo_epi8(b, zero), w));
    _mm_storeu_si128(o + 1, vertical8(_mm_unpackhi_epi8(a, zero), _mm_unpackhi_epi8(b, zero), w));
    if (x == width - 16) break;
  }
}

void resize_horizontal_sse2(const std::uint16_t* row, const ResizePlan& plan, std::uint8_t* out) {
  const int n = plan.dst_w;
  if (n < 8) {
    resize_horizontal_ref(row, plan, out);
    return;
  }
  const std::int32_t* c0 = plan.xs.c0.data();
  const std::uint8_t* w = plan.xs.w.data();
  for (int x = 0;; x += 8) {
    if (x > n - 8) x = n - 8;
    const __m128i lo = horizontal4(row, c0 + x, w + x);
    const __m128i hi = horizontal4(row, c0 + x + 4, w + x + 4);
    const __m128i px = _mm_packus_epi16(_mm_packs_epi32(lo, hi), _mm_setzero_si128());
    _mm_storel_epi64(reinterpret_cast<__m128i*>(out + x), px);
    if (x == n - 8) break;
  }
}

void resize_sse2(GrayView src, MutableGrayView dst, const ResizePlan& plan, std::vector<std::uint16_t>& row) {
  resize_rows(src, dst, plan, row, &resize_vertical_sse2, &resize_horizontal_sse2);
}

}  // namespace ale::features::internal

#endif  // __SSE2__
