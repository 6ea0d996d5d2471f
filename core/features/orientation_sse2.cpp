// SSE2 intensity-centroid moments, bit-exact with ic_moments_ref() (orientation.h). The window is
// the 32 pixels x - 15 .. x + 16 of a row (lane j is u = j - 15), masked to the disk by comparing
// the lane's u with the row's half width. Per pair of rows v, -v: S[j] += b + t in u16 lanes (at
// most 31 * 255 over the disk), and m01 += v (sum b - sum t) with the row sums from psadbw
// (at most 31 * 255, so they and v fit pmaddwd's signed 16-bit operands). Then
// m10 = sum (j - 15) S[j] by pmaddwd.
#include "core/features/orientation.h"

#include <array>

#include "core/features/brief.h"

#if defined(__SSE2__)
#include "core/features/sse2_common.h"

namespace ale::features::internal {

namespace {

inline int sum_i32(__m128i v) {
  v = _mm_add_epi32(v, _mm_shuffle_epi32(v, _MM_SHUFFLE(1, 0, 3, 2)));
  v = _mm_add_epi32(v, _mm_shuffle_epi32(v, _MM_SHUFFLE(2, 3, 0, 1)));
  return _mm_cvtsi128_si32(v);
}

// Row sums of two 16-pixel vectors as 16-bit lanes 0 and 4 (the other lanes 0).
inline __m128i row_sum(__m128i a, __m128i b) {
  const __m128i zero = _mm_setzero_si128();
  return _mm_add_epi64(_mm_sad_epu8(a, zero), _mm_sad_epu8(b, zero));
}

}  // namespace

Moments ic_moments_sse2(GrayView image, int x, int y) {
  static_assert(kPatchRadius == 15, "the 32-pixel window holds the disk of radius 15");
  if (x + 16 >= image.width) return ic_moments_ref(image, x, y);
  static const std::array<int, kPatchRadius + 1> kHalf = [] {
    std::array<int, kPatchRadius + 1> h{};
    for (int v = 0; v <= kPatchRadius; ++v) h[static_cast<std::size_t>(v)] = disk_half_width(v);
    return h;
  }();
  // u of each lane, as signed bytes.
  const __m128i u0 = _mm_setr_epi8(-15, -14, -13, -12, -11, -10, -9, -8, -7, -6, -5, -4, -3, -2, -1, 0);
  const __m128i u1 = _mm_setr_epi8(1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16);
  const __m128i zero = _mm_setzero_si128();
  const std::uint8_t* left = image.row(y) + x - kPatchRadius;
  __m128i s[4];
  __m128i m01 = zero;
  for (int v = 0; v <= kPatchRadius; ++v) {
    // |u| <= half: u < half + 1 and u > -half - 1.
    const int half = kHalf[static_cast<std::size_t>(v)];
    const __m128i above_lo = _mm_set1_epi8(static_cast<char>(half + 1));
    const __m128i below_hi = _mm_set1_epi8(static_cast<char>(-half - 1));
    const __m128i k0 = _mm_and_si128(_mm_cmplt_epi8(u0, above_lo), _mm_cmpgt_epi8(u0, below_hi));
    const __m128i k1 = _mm_and_si128(_mm_cmplt_epi8(u1, above_lo), _mm_cmpgt_epi8(u1, below_hi));
    const __m128i b0 = _mm_and_si128(load16(left + v * image.stride), k0);
    const __m128i b1 = _mm_and_si128(load16(left + v * image.stride + 16), k1);
    if (v == 0) {
      s[0] = _mm_unpacklo_epi8(b0, zero);
      s[1] = _mm_unpackhi_epi8(b0, zero);
      s[2] = _mm_unpacklo_epi8(b1, zero);
      s[3] = _mm_unpackhi_epi8(b1, zero);
      continue;
    }
    const __m128i t0 = _mm_and_si128(load16(left - v * image.stride), k0);
    const __m128i t1 = _mm_and_si128(load16(left - v * image.stride + 16), k1);
    s[0] = _mm_add_epi16(s[0], _mm_add_epi16(_mm_unpacklo_epi8(b0, zero), _mm_unpacklo_epi8(t0, zero)));
    s[1] = _mm_add_epi16(s[1], _mm_add_epi16(_mm_unpackhi_epi8(b0, zero), _mm_unpackhi_epi8(t0, zero)));
    s[2] = _mm_add_epi16(s[2], _mm_add_epi16(_mm_unpacklo_epi8(b1, zero), _mm_unpacklo_epi8(t1, zero)));
    s[3] = _mm_add_epi16(s[3], _mm_add_epi16(_mm_unpackhi_epi8(b1, zero), _mm_unpackhi_epi8(t1, zero)));
    const __m128i diff = _mm_sub_epi16(row_sum(b0, b1), row_sum(t0, t1));
    m01 = _mm_add_epi32(m01, _mm_madd_epi16(diff, _mm_set1_epi16(static_cast<short>(v))));
  }
  // The lane weights u as 16-bit values.
  const __m128i u16[4] = {_mm_srai_epi16(_mm_unpacklo_epi8(u0, u0), 8), _mm_srai_epi16(_mm_unpackhi_epi8(u0, u0), 8),
                          _mm_srai_epi16(_mm_unpacklo_epi8(u1, u1), 8), _mm_srai_epi16(_mm_unpackhi_epi8(u1, u1), 8)};
  __m128i m10 = zero;
  for (int k = 0; k < 4; ++k) m10 = _mm_add_epi32(m10, _mm_madd_epi16(s[k], u16[k]));
  return {sum_i32(m10), sum_i32(m01)};
}

}  // namespace ale::features::internal

#endif  // __SSE2__
