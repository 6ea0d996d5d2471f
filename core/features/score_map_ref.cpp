// Scalar FAST-9 score map: the specification score_map_neon.cpp reproduces (see score_map.h).
// Lanes of up to 16 pixels in fixed-size arrays, so that x86 compilers vectorise the reference.
#include <algorithm>

#include "core/features/score_map.h"

namespace ale::features {

namespace internal {

namespace {

constexpr int kLanes = 16;

// best[i] = max(best[i], the largest over the 16 circular arcs of 9 of the arc's smallest d).
inline void arc_best(const std::uint8_t (&d)[16][kLanes], std::uint8_t (&best)[kLanes]) {
  std::uint8_t m2[16][kLanes], m4[16][kLanes], m8[16][kLanes];
  for (int k = 0; k < 16; ++k)
    for (int i = 0; i < kLanes; ++i) m2[k][i] = std::min(d[k][i], d[(k + 1) & 15][i]);
  for (int k = 0; k < 16; ++k)
    for (int i = 0; i < kLanes; ++i) m4[k][i] = std::min(m2[k][i], m2[(k + 2) & 15][i]);
  for (int k = 0; k < 16; ++k)
    for (int i = 0; i < kLanes; ++i) m8[k][i] = std::min(m4[k][i], m4[(k + 4) & 15][i]);
  for (int k = 0; k < 16; ++k)
    for (int i = 0; i < kLanes; ++i) best[i] = std::max(best[i], std::min(m8[k][i], d[(k + 8) & 15][i]));
}

inline std::uint8_t sat_sub(int a, int b) { return static_cast<std::uint8_t>(a > b ? a - b : 0); }

}  // namespace

void score_row_ref(GrayView image, int y, int x_begin, int x_end, int threshold, std::uint8_t* score_row,
                   std::vector<FastCorner>& corners) {
  int off[16];
  fast9_offsets(image.stride, off);
  const std::uint8_t* row = image.row(y);
  const int t = threshold;
  for (int x = x_begin; x < x_end; x += kLanes) {
    const int n = std::min(kLanes, x_end - x);
    const std::uint8_t* p = row + x;
    // Zero lanes beyond n stay zero: they never pass the compass test below.
    std::uint8_t c[kLanes] = {}, q[4][kLanes] = {};
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < n; ++i) q[j][i] = p[off[4 * j] + i];
    for (int i = 0; i < n; ++i) c[i] = p[i];
    bool any_bright = false, any_dark = false;
    for (int i = 0; i < n; ++i) {
      const int hi = c[i] + t, lo = c[i] - t;
      any_bright |= (q[0][i] > hi || q[2][i] > hi) && (q[1][i] > hi || q[3][i] > hi);
      any_dark |= (q[0][i] < lo || q[2][i] < lo) && (q[1][i] < lo || q[3][i] < lo);
    }
    std::uint8_t best[kLanes] = {};
    if (any_bright || any_dark) {
      std::uint8_t v[16][kLanes] = {};
      for (int k = 0; k < 16; ++k)
        for (int i = 0; i < n; ++i) v[k][i] = p[off[k] + i];
      std::uint8_t d[16][kLanes];
      if (any_bright) {
        for (int k = 0; k < 16; ++k)
          for (int i = 0; i < kLanes; ++i) d[k][i] = sat_sub(v[k][i], c[i]);
        arc_best(d, best);
      }
      if (any_dark) {
        for (int k = 0; k < 16; ++k)
          for (int i = 0; i < kLanes; ++i) d[k][i] = sat_sub(c[i], v[k][i]);
        arc_best(d, best);
      }
    }
    for (int i = 0; i < n; ++i) {
      // score = best - 1; a corner at t exactly when best > t.
      const bool corner = best[i] > t;
      score_row[x + i] = corner ? static_cast<std::uint8_t>(best[i] - 1) : 0;
      if (corner)
        corners.push_back({static_cast<std::int16_t>(x + i), static_cast<std::int16_t>(y),
                           static_cast<std::uint8_t>(best[i] - 1)});
    }
  }
}

}  // namespace internal

void fast9_score_map(GrayView image, PixelRect rect, int threshold, MutableGrayView scores,
                     std::vector<FastCorner>& corners, FastPath path) {
  if (rect.width <= 0 || rect.height <= 0) return;
  if (path == FastPath::kAuto) path = fast_auto_path();
  const bool neon = path == FastPath::kNeon && fast_neon_compiled();
  const int x_end = rect.x + rect.width;
  for (int y = rect.y; y < rect.y + rect.height; ++y) {
    if (neon)
      internal::score_row_neon(image, y, rect.x, x_end, threshold, scores.row(y), corners);
    else
      internal::score_row_ref(image, y, rect.x, x_end, threshold, scores.row(y), corners);
  }
}

void fast9_nonmax_at(GrayView scores, const std::vector<FastCorner>& in, int threshold, std::vector<FastCorner>& out) {
  for (const FastCorner& c : in) {
    const int v = c.score;
    if (v < threshold) continue;
    const std::uint8_t* s = scores.row(c.y) + c.x;
    const std::uint8_t* up = s - scores.stride;
    const std::uint8_t* down = s + scores.stride;
    if (v > up[-1] && v > up[0] && v > up[1] && v > s[-1] && v > s[1] && v > down[-1] && v > down[0] &&
        v > down[1])
      out.push_back(c);
  }
}

}  // namespace ale::features
