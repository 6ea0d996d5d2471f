// SSE2 FAST-9 score map, bit-exact with score_row_ref() (see score_map.h): the NEON kernel's
// algorithm (score_map_neon.cpp) with 16-byte SSE2 vectors, so x86 hosts stop running the scalar
// reference. SSE2 has no unsigned byte compare; a > b is tested as "saturating a - b is non-zero".
// A row's last vector overlaps the previous one (corners only from lanes not emitted yet); a
// segment narrower than 16 pixels is one vector with its extra lanes masked, or the reference when
// the image lacks the pixels to the right.
#include "core/features/score_map.h"

#if defined(__SSE2__)

#include "core/features/sse2_common.h"

namespace ale::features {

namespace internal {

namespace {

inline __m128i arc_best(const __m128i d[16], __m128i best) {
  __m128i m2[16], m4[16];
  for (int k = 0; k < 16; ++k) m2[k] = _mm_min_epu8(d[k], d[(k + 1) & 15]);
  for (int k = 0; k < 16; ++k) m4[k] = _mm_min_epu8(m2[k], m2[(k + 2) & 15]);
  for (int k = 0; k < 16; ++k)
    best = _mm_max_epu8(best, _mm_min_epu8(_mm_min_epu8(m4[k], m4[(k + 4) & 15]), d[(k + 8) & 15]));
  return best;
}

// Lanes (all bits) where neither a nor b exceeds the bound, given a - bound and b - bound saturated.
inline __m128i neither(__m128i a_over, __m128i b_over) {
  return _mm_cmpeq_epi8(_mm_or_si128(a_over, b_over), _mm_setzero_si128());
}

}  // namespace

void fast9_row_sse2(GrayView image, int y, int x_begin, int x_end, int threshold, std::uint8_t* score_row,
              std::vector<FastCorner>& corners) {
  const int narrow = x_end - x_begin < 16 ? x_end - x_begin : 0;
  if (narrow != 0 && x_begin + 16 + kFastRadius > image.width) {
    fast9_row_ref(image, y, x_begin, x_end, threshold, score_row, corners);
    return;
  }
  int off[16];
  fast9_offsets(image.stride, off);
  const std::uint8_t* row = image.row(y);
  const __m128i t = _mm_set1_epi8(static_cast<char>(threshold));
  const __m128i zero = _mm_setzero_si128();
  // Lanes kept of a narrow segment: lane i < narrow.
  const __m128i lane = _mm_setr_epi8(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  const __m128i keep = _mm_cmplt_epi8(lane, _mm_set1_epi8(static_cast<char>(narrow)));
  int done = x_begin;  // lanes below this were emitted already
  for (int x = x_begin;; x += 16) {
    if (narrow == 0 && x > x_end - 16) x = x_end - 16;
    const std::uint8_t* p = row + x;
    const __m128i c = load16(p);
    const __m128i hi = _mm_adds_epu8(c, t);
    const __m128i lo = _mm_subs_epu8(c, t);
    const __m128i v0 = load16(p + off[0]), v4 = load16(p + off[4]), v8 = load16(p + off[8]), v12 = load16(p + off[12]);
    // The compass test of score_map.h: lanes failing it for brighter (resp. darker) arcs.
    const __m128i no_bright = _mm_or_si128(neither(_mm_subs_epu8(v0, hi), _mm_subs_epu8(v8, hi)),
                                           neither(_mm_subs_epu8(v4, hi), _mm_subs_epu8(v12, hi)));
    const __m128i no_dark = _mm_or_si128(neither(_mm_subs_epu8(lo, v0), _mm_subs_epu8(lo, v8)),
                                         neither(_mm_subs_epu8(lo, v4), _mm_subs_epu8(lo, v12)));
    const bool any_bright = _mm_movemask_epi8(no_bright) != 0xFFFF;
    const bool any_dark = _mm_movemask_epi8(no_dark) != 0xFFFF;
    __m128i score = zero;
    if (any_bright || any_dark) {
      __m128i v[16], d[16];
      for (int k = 0; k < 16; ++k) v[k] = load16(p + off[k]);
      __m128i best = zero;
      if (any_bright) {
        for (int k = 0; k < 16; ++k) d[k] = _mm_subs_epu8(v[k], c);
        best = arc_best(d, best);
      }
      if (any_dark) {
        for (int k = 0; k < 16; ++k) d[k] = _mm_subs_epu8(c, v[k]);
        best = arc_best(d, best);
      }
      // score = best - 1 where best > t, else 0.
      score = _mm_andnot_si128(_mm_cmpeq_epi8(_mm_subs_epu8(best, t), zero), _mm_sub_epi8(best, _mm_set1_epi8(1)));
    }
    __m128i* out = reinterpret_cast<__m128i*>(score_row + x);
    if (narrow != 0) {
      score = _mm_and_si128(score, keep);
      _mm_storeu_si128(out, _mm_or_si128(score, _mm_andnot_si128(keep, _mm_loadu_si128(out))));
    } else {
      _mm_storeu_si128(out, score);
    }
    if (any_bright || any_dark) {
      unsigned mask = static_cast<unsigned>(_mm_movemask_epi8(_mm_cmpeq_epi8(score, zero))) ^ 0xFFFFu;
      if (done > x) mask &= ~0u << (done - x);
      alignas(16) std::uint8_t lanes[16];
      if (mask != 0) {
        _mm_store_si128(reinterpret_cast<__m128i*>(lanes), score);
        append_lane_corners(mask, lanes, x, y, corners);
      }
    }
    done = x + 16;
    if (narrow != 0 || x == x_end - 16) break;
  }
}

void score_rect_sse2(GrayView image, PixelRect rect, int threshold, MutableGrayView scores,
                     std::vector<FastCorner>& corners) {
  for (int y = rect.y; y < rect.y + rect.height; ++y)
    fast9_row_sse2(image, y, rect.x, rect.x + rect.width, threshold, scores.row(y), corners);
}

}  // namespace internal
}  // namespace ale::features

#endif  // __SSE2__
