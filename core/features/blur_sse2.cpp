// SSE2 7x7 Gaussian, bit-exact with blur_ref.cpp: 16 pixels per step widened to two 8 x u16 halves
// (the sum is at most 255 * 256 + 128, so u16 never wraps), symmetric taps paired before the
// multiply, one rounding shift and pack. Row ends are covered by one more, overlapping step, as in
// blur_neon.cpp; rows shorter than a vector go to the reference.
#include "core/features/blur.h"

#include "core/features/sse2_common.h"

namespace ale::features::internal {

#if defined(__SSE2__)

namespace {

// (v[0] + v[6]) w0 + (v[1] + v[5]) w1 + (v[2] + v[4]) w2 + v[3] w3 + 128 >> 8 on u16 lanes.
inline __m128i taps7_u16(const __m128i v[7]) {
  const __m128i w0 = _mm_set1_epi16(kBlurTaps[0]), w1 = _mm_set1_epi16(kBlurTaps[1]),
                w2 = _mm_set1_epi16(kBlurTaps[2]), w3 = _mm_set1_epi16(kBlurTaps[3]);
  __m128i s = _mm_add_epi16(_mm_mullo_epi16(v[3], w3), _mm_set1_epi16(128));
  s = _mm_add_epi16(s, _mm_mullo_epi16(_mm_add_epi16(v[0], v[6]), w0));
  s = _mm_add_epi16(s, _mm_mullo_epi16(_mm_add_epi16(v[1], v[5]), w1));
  s = _mm_add_epi16(s, _mm_mullo_epi16(_mm_add_epi16(v[2], v[4]), w2));
  return _mm_srli_epi16(s, 8);
}

inline __m128i taps7(const __m128i v[7]) {
  const __m128i zero = _mm_setzero_si128();
  __m128i lo[7], hi[7];
  for (int k = 0; k < 7; ++k) {
    lo[k] = _mm_unpacklo_epi8(v[k], zero);
    hi[k] = _mm_unpackhi_epi8(v[k], zero);
  }
  return _mm_packus_epi16(taps7_u16(lo), taps7_u16(hi));
}

}  // namespace

void blur_vertical_sse2(GrayView src, int y, std::uint8_t* vrow) {
  const int w = src.width;
  if (w < 16) {
    blur_vertical_ref(src, y, vrow);
    return;
  }
  const std::uint8_t* r[7];
  for (int k = 0; k < 7; ++k) r[k] = src.row(y + k - kBlurRadius);
  for (int x = 0;; x += 16) {
    if (x > w - 16) x = w - 16;
    __m128i v[7];
    for (int k = 0; k < 7; ++k) v[k] = load16(r[k] + x);
    store16(vrow + x, taps7(v));
    if (x == w - 16) break;
  }
}

void blur_horizontal_sse2(const std::uint8_t* vrow, int width, std::uint8_t* out) {
  const int x_end = width - kBlurRadius;
  if (x_end - kBlurRadius < 16) {
    blur_horizontal_ref(vrow, width, out);
    return;
  }
  for (int x = kBlurRadius;; x += 16) {
    if (x > x_end - 16) x = x_end - 16;
    __m128i v[7];
    for (int k = 0; k < 7; ++k) v[k] = load16(vrow + x + k - kBlurRadius);
    store16(out + x, taps7(v));
    if (x == x_end - 16) break;
  }
}

#else

void blur_vertical_sse2(GrayView src, int y, std::uint8_t* vrow) { blur_vertical_ref(src, y, vrow); }
void blur_horizontal_sse2(const std::uint8_t* vrow, int width, std::uint8_t* out) {
  blur_horizontal_ref(vrow, width, out);
}

#endif

}  // namespace ale::features::internal
